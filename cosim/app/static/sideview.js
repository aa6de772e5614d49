// sideview.js -- the side view of the bicycle in the eigenvalue view of `cosim app`
// (cosim/app/export.py bundles it before app.js, which calls it after every redraw): the
// bicycle of the current parameters in Meijaard's nominal configuration, seen from its right,
// rear wheel on the left as in Figure 1 of the paper.
//
//   CosimSideView.draw(canvas, p)   // p: the parameters (Meijaard names, SI units), drawn
//   CosimSideView.describe(p)       // the words of the canvas's aria-label
//   CosimSideView.shown(p)          // the parameters the drawing depends on (name -> value)
//
// Drawn from w, c, lam, rR, rF (the wheels, the ground line, the wheelbase, the steer axis at its
// tilt lam from the vertical through the ground point that lies the trail c ahead of the front
// contact), the centres of mass (xB, zB), (xH, zH) of the rear frame with rider and of the front
// frame, the wheels' centres (their hubs), each a quartered circle whose area grows with its mass
// (mR, mB, mH, mF), and, for a toroidal rear or front tyre, its crown radius tR, tF (a small rear
// view of the tyre: its lateral radius cannot be seen from the side). Nothing else: a moment of
// inertia or g does not change the picture. Heights are -z (Meijaard's z points down). The
// drawing is at the canvas's CSS size times window.devicePixelRatio, like the plots.
(function () {
  "use strict";

  // What the drawing shows; every other parameter leaves it as it is.
  const SHOWN = ["w", "c", "lam", "rR", "rF", "tR", "tF", "xB", "zB", "xH", "zH", "mR", "mB", "mH", "mF"];

  const deg = (rad) => (rad * 180 / Math.PI).toFixed(1);
  const m3 = (x) => x.toFixed(3);
  const num = (x, dflt) => (Number.isFinite(x) ? x : dflt);

  function shown(p) {
    const out = {};
    for (const k of SHOWN) if (k in p) out[k] = p[k];
    return out;
  }

  function describe(p) {
    const parts = [`wheelbase w = ${m3(p.w)} m`, `trail c = ${m3(p.c)} m`,
                   `steer-axis tilt \u03bb = ${deg(p.lam)}\u00b0 from the vertical`,
                   `rear wheel radius r_R = ${m3(p.rR)} m`, `front wheel radius r_F = ${m3(p.rF)} m`];
    if (num(p.tR, 0) > 0) parts.push(`rear crown radius t_R = ${m3(p.tR)} m`);
    if (num(p.tF, 0) > 0) parts.push(`front crown radius t_F = ${m3(p.tF)} m`);
    if ("mB" in p) parts.push(`rear frame with rider ${+p.mB.toPrecision(4)} kg, centre of mass ${m3(-p.zB)} m high`);
    return `side view of the bicycle: ${parts.join(", ")}`;
  }

  // A centre of mass: a circle of radius r [px] with two opposite quarters filled.
  function massSymbol(ctx, x, y, r) {
    ctx.fillStyle = "#fff"; ctx.strokeStyle = "#000"; ctx.lineWidth = 1.2;
    ctx.beginPath(); ctx.arc(x, y, r, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
    ctx.fillStyle = "#000";
    for (const a of [0, Math.PI]) {
      ctx.beginPath(); ctx.moveTo(x, y); ctx.arc(x, y, r, a, a + Math.PI / 2); ctx.closePath(); ctx.fill();
    }
  }

  // A dimension line from (x1, y) to (x2, y) [px] with arrow heads and a label under it.
  function dimension(ctx, x1, x2, y, text, align = "center") {
    ctx.strokeStyle = ctx.fillStyle = "#333"; ctx.lineWidth = 1;
    ctx.beginPath(); ctx.moveTo(x1, y); ctx.lineTo(x2, y); ctx.stroke();
    const s = Math.sign(x2 - x1) || 1, head = Math.min(5, Math.abs(x2 - x1) / 2);
    for (const [x, d] of [[x1, s], [x2, -s]]) {
      ctx.beginPath(); ctx.moveTo(x, y); ctx.lineTo(x + d * head, y - 3); ctx.lineTo(x + d * head, y + 3);
      ctx.closePath(); ctx.fill();
      ctx.beginPath(); ctx.moveTo(x, y - 5); ctx.lineTo(x, y + 5); ctx.stroke();
    }
    ctx.textAlign = align; ctx.textBaseline = "top";
    const tx = align === "center" ? (x1 + x2) / 2 : align === "left" ? Math.max(x1, x2) + 4 : Math.min(x1, x2) - 4;
    ctx.fillText(text, tx, align === "center" ? y + 2 : y - 6);
  }

  function draw(canvas, p) {
    const { ctx, W, H } = CosimCanvas.fit(canvas, 340, 210);
    ctx.clearRect(0, 0, W, H);
    canvas.setAttribute("aria-label", describe(p));

    const { w, c, lam, rR, rF } = p;
    const tR = num(p.tR, 0), tF = num(p.tF, 0);
    const tl = Math.tan(lam), cl = Math.cos(lam);
    // the steer axis from its ground point up to above the highest of the front wheel and frame
    const top = Math.max(2 * rF, 2 * rR, -num(p.zH, 0)) * 1.1 + 0.15;
    const axisAt = (h) => w + c - h * tl;  // x of the steer axis at height h
    const hTop = Math.min(top, 2 * top * cl);  // a steer axis near the horizontal: drawn 2 top long
    const centres = [["R", 0, rR, p.mR], ["B", p.xB, -p.zB, p.mB], ["H", p.xH, -p.zH, p.mH], ["F", w, rF, p.mF]]
      .filter(([, x, h, m]) => Number.isFinite(x) && Number.isFinite(h) && Number.isFinite(m));
    const xs = [-rR, w + rF, w + c, axisAt(hTop), ...centres.map((q) => q[1])];
    const hs = [0, 2 * rR, 2 * rF, hTop, ...centres.map((q) => q[2])];
    const xMin = Math.min(...xs), xMax = Math.max(...xs), hMax = Math.max(...hs), hMin = Math.min(...hs);
    const radius = (m) => Math.min(20, 3 + 1.6 * Math.sqrt(Math.max(m, 0)));  // [px] of a mass symbol
    const crowns = [["t_R", tR, rR], ["t_F", tF, rF]].filter(([, t]) => t > 0);
    const padL = 12 + 80 * crowns.length, padR = 58, padB = 40;
    const padT = 16 + Math.max(0, ...centres.map((q) => radius(q[3])));
    const scale = Math.min((W - padL - padR) / (xMax - xMin), (H - padT - padB) / (hMax - hMin));
    const x0 = padL + ((W - padL - padR) - scale * (xMax - xMin)) / 2;
    const X = (x) => x0 + (x - xMin) * scale, Y = (h) => H - padB - (h - hMin) * scale;
    ctx.font = "11px sans-serif"; ctx.lineCap = "round";

    // the ground
    ctx.strokeStyle = "#555"; ctx.lineWidth = 1.5;
    ctx.beginPath(); ctx.moveTo(4, Y(0)); ctx.lineTo(W - 4, Y(0)); ctx.stroke();
    // the wheels, their radii
    ctx.strokeStyle = "#222"; ctx.lineWidth = 2;
    for (const [x, r] of [[0, rR], [w, rF]]) {
      ctx.beginPath(); ctx.arc(X(x), Y(r), r * scale, 0, 2 * Math.PI); ctx.stroke();
    }
    ctx.lineWidth = 1; ctx.fillStyle = "#333";
    for (const [x, r, name, dir] of [[0, rR, "r_R", -1], [w, rF, "r_F", 1]]) {
      const a = -Math.PI / 2 + dir * Math.PI / 5, ex = X(x) + r * scale * Math.cos(a), ey = Y(r) + r * scale * Math.sin(a);
      ctx.beginPath(); ctx.moveTo(X(x), Y(r)); ctx.lineTo(ex, ey); ctx.stroke();
      ctx.textAlign = "center"; ctx.textBaseline = "top";  // inside the wheel, under its hub
      ctx.fillText(`${name} ${m3(r)}`, X(x), Y(r) + 9);
    }
    // the front frame: the fork from the front hub square to the steer axis, the axis itself
    const foot = (() => {  // the point of the steer axis nearest the front hub
      const ux = -Math.sin(lam), uh = cl, dx = w - (w + c), dh = rF, t = dx * ux + dh * uh;
      return [w + c + t * ux, t * uh];
    })();
    ctx.strokeStyle = "#777"; ctx.lineWidth = 3;
    ctx.beginPath(); ctx.moveTo(X(w), Y(rF)); ctx.lineTo(X(foot[0]), Y(foot[1]));
    ctx.lineTo(X(axisAt(hTop * 0.92)), Y(hTop * 0.92)); ctx.stroke();
    // the rear frame: from the rear hub to the head of the steer axis
    ctx.beginPath(); ctx.moveTo(X(0), Y(rR)); ctx.lineTo(X(axisAt(hTop * 0.8)), Y(hTop * 0.8)); ctx.stroke();
    ctx.strokeStyle = "#c05000"; ctx.lineWidth = 1.5; ctx.setLineDash([6, 3]);
    ctx.beginPath(); ctx.moveTo(X(w + c), Y(0)); ctx.lineTo(X(axisAt(hTop)), Y(hTop)); ctx.stroke();
    ctx.setLineDash([]);
    // lambda: between the vertical and the axis, at the axis's top
    const ax = X(axisAt(hTop)), ay = Y(hTop), arm = Math.min(36, 0.3 * hTop * scale);
    ctx.strokeStyle = "#c05000"; ctx.lineWidth = 1;
    ctx.setLineDash([2, 3]); ctx.beginPath(); ctx.moveTo(ax, ay); ctx.lineTo(ax, ay + arm * 1.3); ctx.stroke();
    ctx.setLineDash([]);
    const down = Math.PI / 2, along = Math.PI / 2 - lam;  // canvas angles (y down) of the vertical and the axis
    ctx.beginPath(); ctx.arc(ax, ay, arm, Math.min(down, along), Math.max(down, along)); ctx.stroke();
    ctx.fillStyle = "#c05000"; ctx.textAlign = "left"; ctx.textBaseline = "middle";
    ctx.fillText(`\u03bb ${deg(lam)}\u00b0`, ax + 7 + Math.max(0, arm * Math.sin(lam)), ay + 4);
    // the centres of mass: area proportional to the mass
    for (const [name, x, h, m] of centres) {
      const r = radius(m);
      massSymbol(ctx, X(x), Y(h), r);
      ctx.fillStyle = "#222"; ctx.textAlign = "left"; ctx.textBaseline = "bottom";
      if (name === "B" || name === "H") ctx.fillText(name, X(x) + r + 2, Y(h) - r / 2);
    }
    // the dimensions under the ground: w from contact to contact, c from the front contact to the
    // steer axis's ground point
    ctx.font = "11px sans-serif";
    dimension(ctx, X(0), X(w), Y(0) + 10, `w ${m3(w)} m`);
    dimension(ctx, X(w), X(w + c), Y(0) + 26, `c ${m3(c)} m`, c >= 0 ? "left" : "right");
    // a crowned tyre: its cross-section seen from behind (the lateral radius), in a corner
    crowns.forEach(([name, t, r], k) => {
      const bx = 8 + k * 80, by = 8, size = 56, s = size / Math.max(2 * r, 2 * t, 1e-9);
      const gx = bx + size / 2, gy = by + size;
      ctx.strokeStyle = "#999"; ctx.lineWidth = 1; ctx.strokeRect(bx - 4, by - 4, size + 8, size + 20);
      ctx.beginPath(); ctx.moveTo(bx - 2, gy); ctx.lineTo(bx + size + 2, gy); ctx.stroke();
      ctx.strokeStyle = "#222"; ctx.lineWidth = 2;
      ctx.beginPath(); ctx.moveTo(gx, gy - 2 * r * s); ctx.lineTo(gx, gy - t * s); ctx.stroke();
      const half = Math.min(Math.PI / 2, Math.acos(Math.max(-1, Math.min(1, 1 - Math.min(r, t) / t))));
      ctx.beginPath(); ctx.arc(gx, gy - t * s, t * s, Math.PI / 2 - half, Math.PI / 2 + half); ctx.stroke();
      ctx.fillStyle = "#222"; ctx.textAlign = "center"; ctx.textBaseline = "top";
      ctx.fillText(`${name} ${m3(t)} m`, gx, gy + 2);
    });
    return { scale };
  }

  window.CosimSideView = { draw, describe, shown, SHOWN };
})();
