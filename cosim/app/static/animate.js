// animate.js: the page of `cosim animate` (classic script, after three.min.js and ride3d.js).
// Reads window.COSIM_ANIMATION = {title, geometry, trajectory, signals, notes} (written by
// cosim/app/animate.py), draws the ride with CosimRide3D and wires the player controls
// (play/pause, scrub, rate, the time shown) and three small plots with a cursor: roll and steer
// angle [deg] against time, and the path of the rear contact point, y (right) against x [m]
// (the scales differ: a lane change of 1 m over 100 m stays visible).
// Tests read window.cosimAnimate = {view, player, data}.
(function () {
  "use strict";
  const data = window.COSIM_ANIMATION;
  const $ = (id) => document.getElementById(id);
  const tr = data.trajectory, t = tr.t, tEnd = t[t.length - 1], t0 = t[0];

  function fail(err) {
    const box = $("error");
    box.hidden = false;
    box.textContent = String(err && err.message || err);
    throw err;
  }

  // --- small line plots on 2-D canvases ------------------------------------------------------
  function setupCanvas(canvas) {
    const ratio = window.devicePixelRatio || 1, w = canvas.clientWidth || 280, h = canvas.clientHeight || 120;
    canvas.width = Math.round(w * ratio);
    canvas.height = Math.round(h * ratio);
    const ctx = canvas.getContext("2d");
    ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
    return { ctx: ctx, w: w, h: h };
  }
  function range(values, padding) {
    let lo = Infinity, hi = -Infinity;
    for (const v of values) { if (v < lo) lo = v; if (v > hi) hi = v; }
    if (!(hi > lo)) { lo -= 1; hi += 1; }
    const pad = padding * (hi - lo);
    return [lo - pad, hi + pad];
  }
  function makePlot(canvas, xs, ys, label) {
    const c = setupCanvas(canvas), m = { l: 38, r: 6, t: 14, b: 16 };
    const [x0, x1] = range(xs, 0), [y0, y1] = range(ys, 0.08);
    const X = (x) => m.l + (x - x0) / (x1 - x0) * (c.w - m.l - m.r);
    const Y = (y) => c.h - m.b - (y - y0) / (y1 - y0) * (c.h - m.t - m.b);
    const base = document.createElement("canvas");
    base.width = canvas.width; base.height = canvas.height;
    function drawBase(ctx) {
      ctx.clearRect(0, 0, c.w, c.h);
      ctx.fillStyle = "#5b6672"; ctx.font = "11px system-ui, sans-serif";
      ctx.fillText(label, m.l, 10);
      ctx.fillText(y1.toPrecision(3), 2, m.t + 8); ctx.fillText(y0.toPrecision(3), 2, c.h - m.b);
      ctx.fillText(x0.toPrecision(3), m.l, c.h - 3);
      ctx.textAlign = "right"; ctx.fillText(x1.toPrecision(3), c.w - m.r, c.h - 3); ctx.textAlign = "left";
      ctx.strokeStyle = "#d4dae0"; ctx.strokeRect(m.l, m.t, c.w - m.l - m.r, c.h - m.t - m.b);
      if (y0 < 0 && y1 > 0) { ctx.beginPath(); ctx.moveTo(m.l, Y(0)); ctx.lineTo(c.w - m.r, Y(0)); ctx.stroke(); }
      ctx.strokeStyle = "#1f4e9c"; ctx.lineWidth = 1.2; ctx.beginPath();
      for (let i = 0; i < xs.length; i++) { if (i) ctx.lineTo(X(xs[i]), Y(ys[i])); else ctx.moveTo(X(xs[i]), Y(ys[i])); }
      ctx.stroke(); ctx.lineWidth = 1;
    }
    const baseCtx = base.getContext("2d");
    baseCtx.setTransform(canvas.width / c.w, 0, 0, canvas.height / c.h, 0, 0);
    drawBase(baseCtx);
    return function cursor(x, y) {
      c.ctx.setTransform(1, 0, 0, 1, 0, 0);
      c.ctx.clearRect(0, 0, canvas.width, canvas.height);
      c.ctx.drawImage(base, 0, 0);
      c.ctx.setTransform(canvas.width / c.w, 0, 0, canvas.height / c.h, 0, 0);
      c.ctx.fillStyle = "#c0392b"; c.ctx.beginPath(); c.ctx.arc(X(x), Y(y), 3, 0, 2 * Math.PI); c.ctx.fill();
    };
  }

  const DEG = 180 / Math.PI;
  let plots = [];
  function buildPlots() {
    plots = [
      makePlot($("plot-phi"), t, tr.phi.map((v) => v * DEG), "roll φ [deg] vs t [s]"),
      makePlot($("plot-delta"), t, tr.delta.map((v) => v * DEG), "steer δ [deg] vs t [s]"),
      makePlot($("plot-path"), tr.x, tr.y, "path: y right [m] vs x [m]"),
    ];
  }

  // --- the view and the player ---------------------------------------------------------------
  let view, player;
  try {
    $("notes").textContent = (data.notes || []).join("; ");
    view = CosimRide3D.createView($("ride"), data.geometry, { rider: true, follow: true });
    buildPlots();
    const scrub = $("scrub"), timeText = $("time"), playButton = $("play");
    const onFrame = (time) => {
      timeText.textContent = "t = " + time.toFixed(2) + " s / " + tEnd.toFixed(2) + " s";
      if (!scrub.matches(":active")) scrub.value = String(Math.round(1000 * (time - t0) / Math.max(tEnd - t0, 1e-12)));
      const q = CosimRide3D.poseAt(tr, time);
      plots[0](time, q.phi * DEG); plots[1](time, q.delta * DEG); plots[2](q.x, q.y);
      playButton.textContent = player && player.state.playing ? "Pause" : "Play";
    };
    const resize = () => {
      const canvas = $("ride");
      view.resize(canvas.clientWidth, canvas.clientHeight);
      if (player) player.seek(player.state.time);
    };
    view.resize($("ride").clientWidth, $("ride").clientHeight);
    player = CosimRide3D.createPlayer(view, tr, {
      rate: 1, onFrame: onFrame, onEnd: () => { playButton.textContent = "Play"; },
    });
    onFrame(player.state.time);
    playButton.addEventListener("click", () => {
      if (player.state.playing) player.pause(); else player.play();
      playButton.textContent = player.state.playing ? "Pause" : "Play";
    });
    scrub.addEventListener("input", () => player.seek(t0 + (tEnd - t0) * Number(scrub.value) / 1000));
    $("rate").addEventListener("change", (ev) => player.setRate(Number(ev.target.value)));
    // camera presets: azimuth from the heading [rad] (pi: from behind, -pi/2: from the left), elevation [rad]
    const CAMERAS = { chase: [-2.2, 0.28], side: [-Math.PI / 2, 0.12], behind: [Math.PI, 0.3], front: [0.35, 0.2],
      top: [Math.PI, 1.45] };
    $("camera").addEventListener("change", (ev) => {
      [view.orbit.azimuth, view.orbit.elevation] = CAMERAS[ev.target.value];
      if (!player.state.playing) view.render();
    });
    document.addEventListener("keydown", (ev) => {
      if (ev.code !== "Space" || /^(INPUT|SELECT|BUTTON)$/.test(ev.target.tagName)) return;
      ev.preventDefault();
      playButton.click();
    });
    window.addEventListener("resize", resize);
  } catch (err) {
    fail(err);
  }
  window.cosimAnimate = { view: view, player: player, data: data };
})();
