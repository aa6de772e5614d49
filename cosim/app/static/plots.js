// plots.js -- the plots beside the 3-D ride of `cosim app` (bundled by cosim/app/export.py before
// ride.js): roll, steer and heading vs time and the path y(x) of the rear contact point on one 2-D
// canvas, one or two rides (the demo's ride solid, its comparison dashed), a cursor at the player's time.
//
//   const plot = CosimPlots.create(canvas);
//   plot.setRides([{label, color, dashed?, t: [...], phi, delta, psi, x, y}, ...]);
//   plot.setCursor(time);      // [s] a vertical line in the time plots, a dot on the path
//   plot.setTarget({label, x: [...], y: [...]} or null);  // a path to follow, dashed grey
//   plot.draws                 // frames drawn (tests)
//
// The path is drawn seen from above with x (forward at yaw 0) to the right and y (to the right of
// the rider, Meijaard's axes: z down) downwards, at equal scales, so it looks like the ground.
(function () {
  "use strict";

  const PANELS = [
    { signal: "phi", label: "roll \u03c6 [rad]" },
    { signal: "delta", label: "steer \u03b4 [rad]" },
    { signal: "psi", label: "heading \u03c8 [rad]" },
  ];

  function niceRange(lo, hi) {
    if (!(hi > lo)) { const m = Number.isFinite(lo) ? Math.abs(lo) || 1 : 1; return [lo - 0.1 * m || -1, hi + 0.1 * m || 1]; }
    const pad = 0.06 * (hi - lo);
    return [lo - pad, hi + pad];
  }

  function extent(rides, key) {
    let lo = Infinity, hi = -Infinity;
    for (const r of rides) for (const v of r[key]) { if (v < lo) lo = v; if (v > hi) hi = v; }
    return [lo, hi];
  }

  function ticks(lo, hi, count) {
    const raw = (hi - lo) / count, mag = Math.pow(10, Math.floor(Math.log10(raw)));
    const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => s >= raw) || raw;
    const out = [];
    for (let v = Math.ceil(lo / step) * step; v <= hi + 1e-12; v += step) out.push(Math.abs(v) < 1e-12 ? 0 : v);
    return out;
  }

  function create(canvas) {
    const ctx = canvas.getContext("2d");
    let rides = [], cursor = null, target = null;
    const plot = { draws: 0 };

    // A framed panel with ticks; Y maps values upwards, or downwards with `down` (the path's y).
    function frame(x0, y0, w, h, xr, yr, label, xlabel, down = false) {
      ctx.strokeStyle = "#999"; ctx.lineWidth = 1; ctx.strokeRect(x0, y0, w, h);
      ctx.fillStyle = "#444"; ctx.font = "11px sans-serif";
      ctx.textAlign = "right"; ctx.textBaseline = "middle";
      const Y = (v) => (down ? y0 + (v - yr[0]) / (yr[1] - yr[0]) * h : y0 + h - (v - yr[0]) / (yr[1] - yr[0]) * h), X = (v) => x0 + (v - xr[0]) / (xr[1] - xr[0]) * w;
      for (const v of ticks(yr[0], yr[1], 4)) {
        ctx.fillText(+v.toPrecision(3) + "", x0 - 3, Y(v));
        ctx.strokeStyle = "#eee"; ctx.beginPath(); ctx.moveTo(x0, Y(v)); ctx.lineTo(x0 + w, Y(v)); ctx.stroke();
      }
      ctx.textAlign = "center"; ctx.textBaseline = "top";
      for (const v of ticks(xr[0], xr[1], 5)) ctx.fillText(+v.toPrecision(3) + "", X(v), y0 + h + 2);
      ctx.textAlign = "left"; ctx.textBaseline = "bottom"; ctx.fillText(label, x0 + 2, y0 - 1);
      if (xlabel) { ctx.textAlign = "right"; ctx.fillText(xlabel, x0 + w, y0 - 1); }
      return { X, Y };
    }

    function line(r, xs, ys, X, Y, until) {
      ctx.strokeStyle = r.color; ctx.lineWidth = 1.5; ctx.setLineDash(r.dashed ? [5, 4] : []);
      ctx.beginPath();
      for (let i = 0; i < xs.length; i++) {
        if (until !== undefined && r.t[i] > until) break;
        if (i === 0) ctx.moveTo(X(xs[i]), Y(ys[i])); else ctx.lineTo(X(xs[i]), Y(ys[i]));
      }
      ctx.stroke(); ctx.setLineDash([]);
    }

    // Drawn at the canvas's CSS size times window.devicePixelRatio (canvas.js), in CSS pixels.
    function draw() {
      const { W, H } = CosimCanvas.fit(canvas, 600, 420);
      ctx.textAlign = "left"; ctx.textBaseline = "alphabetic";
      ctx.fillStyle = "#fff"; ctx.fillRect(0, 0, W, H);
      plot.draws++;
      if (!rides.length) return;
      const left = 48, gap = 26, tw = Math.floor(W * 0.5) - left - 10, th = Math.floor((H - 30 - gap * 3) / 3);
      const tr = [0, Math.max(...rides.map((r) => r.t[r.t.length - 1])) || 1];
      PANELS.forEach((p, k) => {
        const y0 = 16 + k * (th + gap);
        const { X, Y } = frame(left, y0, tw, th, tr, niceRange(...extent(rides, p.signal)), p.label,
                               k === PANELS.length - 1 ? "time [s]" : "");
        for (const r of rides) line(r, r.t, r[p.signal], X, Y);
        if (cursor !== null) {
          ctx.strokeStyle = "#e67e00"; ctx.lineWidth = 1.5; ctx.beginPath();
          ctx.moveTo(X(cursor), y0); ctx.lineTo(X(cursor), y0 + th); ctx.stroke();
        }
      });
      // the path seen from above: x to the right, y downwards, at equal scales unless that would
      // flatten it (a lane change: 1 m over 70 m), then y stretched and the stretch shown (never
      // squeezed: a path that is long in y is drawn narrow in x, as it is)
      const px0 = left + tw + 60, pw = W - px0 - 10, py0 = 16, ph = H - 46;
      const onPath = target ? [...rides, target] : rides;  // the target in view too
      let [xl, xh] = niceRange(...extent(onPath, "x")), [yl, yh] = niceRange(...extent(onPath, "y"));
      const sx = pw / (xh - xl), sy = ph / (yh - yl);
      let stretch = 1;
      if (sy / sx > 4) stretch = sy / sx / 2;  // y alone would fill 4x more than equal scales allow
      const scaleX = Math.min(sx, sy / stretch), scaleY = scaleX * stretch;
      const xc = (xl + xh) / 2, yc = (yl + yh) / 2;
      xl = xc - pw / scaleX / 2; xh = xc + pw / scaleX / 2; yl = yc - ph / scaleY / 2; yh = yc + ph / scaleY / 2;
      const title = "path y(x) [m], seen from above" + (Math.abs(stretch - 1) > 1e-9 ?
        ` (y scale \u00d7${+stretch.toPrecision(2)})` : "");
      const { X, Y } = frame(px0, py0, pw, ph, [xl, xh], [yl, yh], title, "", true);
      if (target) line({ ...target, color: "#777", dashed: true }, target.x, target.y, X, Y);
      for (const r of rides) line(r, r.x, r.y, X, Y);
      ctx.fillStyle = "#444"; ctx.textAlign = "left"; ctx.textBaseline = "top";
      ctx.fillText("y [m] \u2193 (right of the rider)", px0 + 4, py0 + 4);
      ctx.textAlign = "right"; ctx.textBaseline = "bottom";
      ctx.fillText("x [m] \u2192", px0 + pw - 4, py0 + ph - 4);
      if (cursor !== null) {
        for (const r of rides) {
          let i = 0;
          while (i < r.t.length - 1 && r.t[i + 1] <= cursor) i++;
          ctx.fillStyle = "#e67e00"; ctx.beginPath(); ctx.arc(X(r.x[i]), Y(r.y[i]), 4, 0, 2 * Math.PI); ctx.fill();
        }
      }
      // legend
      ctx.textAlign = "left"; ctx.textBaseline = "middle";  // (the x label above left it "right")
      const legend = target ? [...rides, { label: target.label, color: "#777", dashed: true }] : rides;
      legend.forEach((r, k) => {
        const lx = px0 + 6, ly = py0 + 24 + 14 * k;  // under the axis label, top left
        ctx.strokeStyle = r.color; ctx.lineWidth = 2; ctx.setLineDash(r.dashed ? [5, 4] : []);
        ctx.beginPath(); ctx.moveTo(lx, ly); ctx.lineTo(lx + 22, ly); ctx.stroke(); ctx.setLineDash([]);
        ctx.fillStyle = "#222"; ctx.fillText(r.label, lx + 28, ly);
      });
    }

    plot.setRides = (list) => { rides = list.filter((r) => r && r.t.length); cursor = null; draw(); };
    plot.setCursor = (time) => { cursor = time; draw(); };
    plot.setTarget = (path) => { target = path && path.x.length ? path : null; draw(); };
    plot.redraw = draw;
    draw();
    return plot;
  }

  window.CosimPlots = { create, PANELS };
})();
