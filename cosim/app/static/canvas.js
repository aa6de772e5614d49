// A 2-D canvas drawn at its CSS size times window.devicePixelRatio, so that it is crisp on HiDPI
// screens and projectors: the backing store follows the box (resized only when it changed, which
// clears it) and the context is scaled, so that callers draw in CSS pixels.
(function () {
  "use strict";

  // fit(canvas, width, height): {ctx, W, H}, W x H the CSS size [px] (width, height where the
  // canvas has no layout box yet, e.g. while hidden).
  function fit(canvas, width, height) {
    const dpr = window.devicePixelRatio || 1;
    const W = canvas.clientWidth || width, H = canvas.clientHeight || height;
    const bw = Math.round(W * dpr), bh = Math.round(H * dpr);
    if (canvas.width !== bw) canvas.width = bw;
    if (canvas.height !== bh) canvas.height = bh;
    const ctx = canvas.getContext("2d");
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    return { ctx, W, H };
  }

  window.CosimCanvas = { fit };
})();
