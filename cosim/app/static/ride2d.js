// ride2d.js -- the ride drawn in 2-D, for browsers without WebGL (classic script, bundled by
// cosim/app/export.py before ride.js). Defines window.CosimRide2D:
//   webglAvailable() -> whether this browser gives a WebGL context (probed once, on a canvas of
//       its own, so that the page's canvas stays free for a 2-D context)
//   createView(canvas, geometry) -> a view with the interface of CosimRide3D.createView's
//       (setPose(q), setPath(points), render(), frames, resize(width, height), dispose(),
//       animating), plus setTarget(points) (a path to follow, dashed grey)
// so that CosimRide3D.createPlayer plays a ride in it as in the 3-D view.
//
// The canvas shows two pictures side by side: on the left the ground seen from above (x forward
// to the right, y to the rider's right downwards: Meijaard's axes, as the path plot of plots.js),
// the path so far and the bicycle as its two wheels (the front one turned by the steer angle);
// on the right the bicycle seen from behind, leaning by the roll angle phi, with a dial of the
// steer angle delta. Roll and steer are positive to the right (Meijaard et al. 2007).
(function () {
  "use strict";

  let probed = null;
  function webglAvailable() {
    if (probed === null) {
      try {
        const c = document.createElement("canvas");
        const gl = window.WebGLRenderingContext ? (c.getContext("webgl2") || c.getContext("webgl")) : null;
        probed = !!gl;
        const lose = gl && gl.getExtension("WEBGL_lose_context");
        if (lose) lose.loseContext();  // the probe's context is not kept
      } catch (e) {
        probed = false;
      }
    }
    return probed;
  }

  const DEG = 180 / Math.PI;

  function createView(canvas, geometry) {
    const ctx = canvas.getContext("2d");
    if (!ctx) throw new Error("CosimRide2D: this canvas gives no 2-D context");
    const w = geometry.w || 1.02, rR = geometry.rR || 0.3, rF = geometry.rF || 0.35;
    const lam = geometry.lam || 0;
    let pose = { x: 0, y: 0, psi: 0, phi: 0, delta: 0 }, path = [], target = null;
    let W = canvas.clientWidth || 400, H = canvas.clientHeight || 300;

    function line(x0, y0, x1, y1) { ctx.beginPath(); ctx.moveTo(x0, y0); ctx.lineTo(x1, y1); ctx.stroke(); }

    // The ground from above, centred on the bicycle: `span` metres across.
    function topView(x0, y0, width, height) {
      const span = Math.max(8, 6 * w), k = width / span;
      const cx = x0 + width / 2, cy = y0 + height / 2;
      const X = (x) => cx + (x - pose.x) * k, Y = (y) => cy + (y - pose.y) * k;
      ctx.save();
      ctx.beginPath(); ctx.rect(x0, y0, width, height); ctx.clip();
      ctx.fillStyle = "#e8efe0"; ctx.fillRect(x0, y0, width, height);
      ctx.strokeStyle = "#d0d8c8"; ctx.lineWidth = 1;  // a 1-m grid: the motion shows on the ground
      for (let gx = Math.ceil(pose.x - span / 2); gx <= pose.x + span / 2; gx++) line(X(gx), y0, X(gx), y0 + height);
      for (let gy = Math.ceil(pose.y - span / 2); gy <= pose.y + span / 2; gy++) line(x0, Y(gy), x0 + width, Y(gy));
      const polyline = (points) => {
        ctx.beginPath();
        points.forEach(([px, py], i) => (i ? ctx.lineTo(X(px), Y(py)) : ctx.moveTo(X(px), Y(py))));
        ctx.stroke();
      };
      if (target && target.length) {
        ctx.strokeStyle = "#777"; ctx.lineWidth = 2; ctx.setLineDash([6, 5]); polyline(target); ctx.setLineDash([]);
      }
      if (path.length) { ctx.strokeStyle = "#1f5fbf"; ctx.lineWidth = 2; polyline(path); }
      // the bicycle: rear wheel along the heading, front wheel turned by the steer angle on the
      // ground (about delta cos(lam) for a small lean)
      const c = Math.cos(pose.psi), s = Math.sin(pose.psi);
      const fx = pose.x + w * c, fy = pose.y + w * s;
      const turn = pose.psi + pose.delta * Math.cos(lam);
      ctx.lineCap = "round";
      ctx.strokeStyle = "#222"; ctx.lineWidth = 4;
      line(X(pose.x - rR * c), Y(pose.y - rR * s), X(pose.x + rR * c), Y(pose.y + rR * s));
      line(X(fx - rF * Math.cos(turn)), Y(fy - rF * Math.sin(turn)), X(fx + rF * Math.cos(turn)), Y(fy + rF * Math.sin(turn)));
      ctx.strokeStyle = "#c0392b"; ctx.lineWidth = 3;
      line(X(pose.x), Y(pose.y), X(fx), Y(fy));
      ctx.lineCap = "butt";
      ctx.restore();
      ctx.strokeStyle = "#999"; ctx.lineWidth = 1; ctx.strokeRect(x0, y0, width, height);
      ctx.fillStyle = "#222"; ctx.font = "12px sans-serif"; ctx.textAlign = "left"; ctx.textBaseline = "top";
      ctx.fillText("from above (forward \u2192)", x0 + 4, y0 + 4);
    }

    // The bicycle from behind: ground, wheel and rider leaning by phi; a dial of the steer angle.
    function rearView(x0, y0, width, height) {
      ctx.fillStyle = "#eef3f8"; ctx.fillRect(x0, y0, width, height);
      const ground = y0 + height * 0.78, cx = x0 + width / 2, k = Math.min(width, height) * 0.5 / 1.8;
      ctx.strokeStyle = "#6b7a5a"; ctx.lineWidth = 2; line(x0, ground, x0 + width, ground);
      const lean = pose.phi, ux = Math.sin(lean), uy = -Math.cos(lean);  // up the leaning bicycle
      const at = (d) => [cx + ux * d * k, ground + uy * d * k];
      ctx.lineCap = "round";
      ctx.strokeStyle = "#222"; ctx.lineWidth = 6; line(...at(0), ...at(2 * rR));  // the wheel, edge on
      ctx.strokeStyle = "#c0392b"; ctx.lineWidth = 4; line(...at(2 * rR), ...at(1.1));  // the frame
      ctx.strokeStyle = "#1f4fd0"; ctx.lineWidth = 5; line(...at(1.1), ...at(1.6));  // the rider
      const [hx, hy] = at(1.72);
      ctx.fillStyle = "#1f4fd0"; ctx.beginPath(); ctx.arc(hx, hy, 0.1 * k, 0, 2 * Math.PI); ctx.fill();
      ctx.lineCap = "butt";
      ctx.setLineDash([4, 4]); ctx.strokeStyle = "#999"; ctx.lineWidth = 1;
      line(cx, ground, cx, ground - 1.8 * k); ctx.setLineDash([]);
      // the steer dial: a needle from straight up, turned by delta (right: clockwise)
      const dx = x0 + width - 0.2 * Math.min(width, height) - 6, dy = y0 + 0.2 * Math.min(width, height) + 18;
      const r = 0.18 * Math.min(width, height);
      ctx.strokeStyle = "#999"; ctx.lineWidth = 1; ctx.beginPath(); ctx.arc(dx, dy, r, 0, 2 * Math.PI); ctx.stroke();
      const d = Math.max(-Math.PI, Math.min(Math.PI, pose.delta));
      ctx.strokeStyle = "#222"; ctx.lineWidth = 3; line(dx, dy, dx + r * Math.sin(d), dy - r * Math.cos(d));
      ctx.fillStyle = "#222"; ctx.font = "12px sans-serif"; ctx.textAlign = "left"; ctx.textBaseline = "top";
      ctx.fillText("from behind", x0 + 4, y0 + 4);
      const side = (x) => (Math.abs(x) < 0.5 / DEG ? "" : x > 0 ? " right" : " left");
      ctx.fillText(`lean ${Math.abs(lean * DEG).toFixed(0)}\u00b0${side(lean)}`, x0 + 4, y0 + height - 34);
      ctx.fillText(`steer ${Math.abs(pose.delta * DEG).toFixed(0)}\u00b0${side(pose.delta)}`, x0 + 4, y0 + height - 18);
      ctx.textAlign = "center"; ctx.fillText("steer", dx, dy + r + 2);
      ctx.strokeStyle = "#999"; ctx.lineWidth = 1; ctx.strokeRect(x0, y0, width, height);
    }

    const view = {
      frames: 0,
      animating: false,
      pose: pose,
      setPose(q) { pose = { ...pose, ...q }; view.pose = pose; },
      setPath(points) { path = points.slice(); },
      setTarget(points) { target = points ? points.slice() : null; },
      render() {
        const dpr = window.devicePixelRatio || 1;
        ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
        ctx.fillStyle = "#fff"; ctx.fillRect(0, 0, W, H);
        const split = Math.round(W * 0.6);
        topView(0, 0, split - 3, H);
        rearView(split + 3, 0, W - split - 3, H);
        view.frames += 1;
      },
      resize(width, height) {
        const dpr = window.devicePixelRatio || 1;
        W = width; H = height;
        canvas.width = Math.round(width * dpr);
        canvas.height = Math.round(height * dpr);
      },
      dispose() {},
    };
    view.resize(W, H);
    return view;
  }

  window.CosimRide2D = { createView, webglAvailable };
})();
