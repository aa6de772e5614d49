// app.js -- the page of `cosim app` (cosim/app/export.py bundles it after its data, ml-matrix and
// fmu.js): eigenvalues of the linear Whipple bicycle vs speed from the WebAssembly FMU.
//
// A(v) is not computed here: for each speed the FMU instance is reset, given the parameters and
// the speed, initialized, and A is the directional derivatives of der(phi), der(delta),
// der(phi_dot), der(delta_dot) with respect to phi, delta, phi_dot, delta_dot
// (fmi2GetDirectionalDerivative, exact: CasADi's forward mode). The eigenvalues of A are
// ml-matrix's EigenvalueDecomposition (JAMA's Hessenberg-QR). Weave and capsize speeds are the
// sign changes of the largest real part of the oscillatory / real eigenvalues over the sweep,
// refined by bisection with the same routine, with the definitions of cosim.analytic.whipple.
//
// window.cosimApp is the page's state for tests: {ready, error, set, parameters, speed,
// eigenvalues [[re, im] x 4] at the speed, weave, capsize (m/s or null), sweep {speeds, evs, weave,
// capsize}, lastRedrawMs [ms] and evaluations (linearizations of the FMU) of the last redraw,
// redraws}.
(function () {
  "use strict";
  const DATA = window.COSIM_DATA;
  const state = { ready: false, error: null, set: null, parameters: {}, speed: DATA.speeds.default,
                  eigenvalues: [], weave: null, capsize: null, sweep: null, lastRedrawMs: null, evaluations: 0,
                  redraws: 0 };
  window.cosimApp = state;

  const $ = (id) => document.getElementById(id);
  const base64Bytes = (text) => Uint8Array.from(atob(text), (ch) => ch.charCodeAt(0));

  // Eigenvalues with |Im| below this count as real (as cosim.analytic.whipple._imag_tol).
  const imagTol = (re, im) => 1e-7 * Math.max(1, Math.hypot(re, im));

  class Linearization {
    constructor(fmu) {
      this.instance = fmu.instantiate({ name: "app" });
      // every set has the same Meijaard parameters (export.py checks it): one writer for all
      this.names = Object.keys(Object.values(DATA.parameterSets)[0]);
      this.write = this.instance.writer([...this.names, "v"]);
      // the derivatives of the lateral states, found by the `derivative` attribute of NAME.json
      const vars = fmu.description.variables;
      const derivativeOf = new Map(vars.filter((v) => v.derivative).map((v) => [vars[v.derivative - 1].name, v.name]));
      const derivatives = DATA.lateralStates.map((s) => {
        if (!derivativeOf.has(s)) throw new Error(`${fmu.modelName} has no state ${s}`);
        return derivativeOf.get(s);
      });
      this.jacobian = this.instance.directional(derivatives, DATA.lateralStates);
      this.evaluations = 0;
    }

    // A(v) of the parameters p (name -> value): a new initialization of the instance.
    stateMatrix(p, v) {
      const inst = this.instance;
      inst.reset();
      this.write([...this.names.map((n) => p[n]), v]);
      inst.setupExperiment({ startTime: 0 });
      inst.enterInitializationMode();
      inst.exitInitializationMode();
      this.evaluations++;
      return this.jacobian.jacobian();
    }

    // The eigenvalues [[re, im], ...] of A(v), sorted by real, then imaginary part.
    eigenvalues(p, v) {
      const e = new mlMatrix.EigenvalueDecomposition(new mlMatrix.Matrix(this.stateMatrix(p, v)));
      const re = e.realEigenvalues, im = e.imaginaryEigenvalues;
      return re.map((r, i) => [r, im[i]]).sort((a, b) => a[0] - b[0] || a[1] - b[1]);
    }
  }

  // Largest real part among the oscillatory (weave) or real (capsize) eigenvalues, NaN if none.
  function modeMax(ev, oscillatory) {
    let best = NaN;
    for (const [re, im] of ev) {
      const osc = Math.abs(im) > imagTol(re, im);
      if (osc === oscillatory && !(re <= best)) best = re;
    }
    return best;
  }

  // Bisection of f on [a, b] where f(a) and f(b) are on opposite sides of zero (f(a) > 0 >= f(b)
  // or f(a) < 0 <= f(b), as `before` tells): to the last bits of the speed.
  function bisect(f, a, b, positiveFirst) {
    const before = (x) => { const y = f(x); return positiveFirst ? y > 0 : y < 0; };
    for (let k = 0; k < 100 && b - a > 4e-16 * Math.max(1, Math.abs(b)); k++) {
      const m = 0.5 * (a + b);
      if (m <= a || m >= b) break;
      if (before(m)) a = m; else b = m;
    }
    return 0.5 * (a + b);
  }

  // Weave speed: first sweep interval with oscillatory eigenvalues at both ends across which
  // their largest real part goes from > 0 to <= 0; capsize speed: from the weave speed on (else
  // 0), the first where the largest real eigenvalue goes from < 0 to >= 0 (cosim.analytic.whipple).
  function criticalSpeeds(lin, p, speeds, evs) {
    const wr = evs.map((ev) => modeMax(ev, true)), rr = evs.map((ev) => modeMax(ev, false));
    let weave = null;
    for (let i = 0; i + 1 < speeds.length && weave === null; i++) {
      if (wr[i] > 0 && !(wr[i + 1] > 0) && !Number.isNaN(wr[i + 1]))
        weave = wr[i + 1] === 0 ? speeds[i + 1]
          : bisect((v) => modeMax(lin.eigenvalues(p, v), true), speeds[i], speeds[i + 1], true);
    }
    const from = weave === null ? speeds[0] : weave;
    let capsize = null;
    for (let i = 0; i + 1 < speeds.length && capsize === null; i++) {
      if (speeds[i + 1] < from) continue;
      // the interval that holds `from` starts there; its left end is then re-evaluated
      const a = Math.max(speeds[i], from), ra = a === speeds[i] ? rr[i] : modeMax(lin.eigenvalues(p, a), false);
      if (ra < 0 && rr[i + 1] >= 0)
        capsize = rr[i + 1] === 0 ? speeds[i + 1]
          : bisect((v) => modeMax(lin.eigenvalues(p, v), false), a, speeds[i + 1], false);
    }
    return { weave, capsize };
  }

  function sweep(lin, p) {
    const { min, max, num } = DATA.speeds;
    const speeds = Array.from({ length: num }, (_, k) => min + (max - min) * k / (num - 1));
    speeds[num - 1] = max;
    const evs = speeds.map((v) => lin.eigenvalues(p, v));
    return { speeds, evs, ...criticalSpeeds(lin, p, speeds, evs) };
  }

  // --- the plot: real parts (dots) and imaginary parts (grey) vs speed, Figure 9 style -------
  function draw(canvas, s) {
    const ctx = canvas.getContext("2d"), W = canvas.width, H = canvas.height;
    const left = 56, right = 12, top = 14, bottom = 40;
    const { min, max } = DATA.speeds, yMin = -10, yMax = 10;
    const X = (v) => left + (v - min) / (max - min) * (W - left - right);
    const Y = (y) => top + (yMax - Math.max(yMin, Math.min(yMax, y))) / (yMax - yMin) * (H - top - bottom);
    ctx.clearRect(0, 0, W, H);
    ctx.font = "12px sans-serif";
    ctx.strokeStyle = "#ccc"; ctx.fillStyle = "#444"; ctx.lineWidth = 1;
    grid(ctx, { X, Y, left, right, top, bottom, W, H }, [min, max, 1, 4], [yMin, yMax, 2]);
    ctx.strokeStyle = "#000";
    ctx.beginPath(); ctx.moveTo(left, Y(0)); ctx.lineTo(W - right, Y(0)); ctx.stroke();
    ctx.fillText("speed v [m/s]", W / 2 - 40, H - 8);
    ctx.save(); ctx.translate(14, H / 2 + 40); ctx.rotate(-Math.PI / 2);
    ctx.fillText("Re \u03bb, |Im \u03bb| (grey) [1/s]", 0, 0); ctx.restore();
    // the self-stable band
    if (s.weave !== null) {
      ctx.fillStyle = "rgba(60, 170, 60, 0.12)";
      const end = s.capsize === null ? max : s.capsize;
      ctx.fillRect(X(s.weave), top, X(end) - X(s.weave), H - top - bottom);
    }
    s.speeds.forEach((v, k) => {
      for (const [re, im] of s.evs[k]) {  // what lies outside the axes is not drawn
        const osc = Math.abs(im) > imagTol(re, im);
        if (osc && Math.abs(im) <= yMax) {
          ctx.fillStyle = "#999"; ctx.fillRect(X(v) - 1, Y(Math.abs(im)) - 1, 2, 2);
        }
        if (re < yMin || re > yMax) continue;
        ctx.fillStyle = osc ? "#c03030" : "#2050c0";
        ctx.fillRect(X(v) - 1.5, Y(re) - 1.5, 3, 3);
      }
    });
    ctx.strokeStyle = "#e08000"; ctx.lineWidth = 1.5;
    ctx.beginPath(); ctx.moveTo(X(state.speed), top); ctx.lineTo(X(state.speed), H - bottom); ctx.stroke();
  }

  // Grid lines with their labels: xs = [first, last, step, label offset], ys = [first, last, step]
  // (the stroke and fill styles are the caller's).
  function grid(ctx, { X, Y, left, right, top, bottom, W, H }, xs, ys) {
    const [x0, x1, dx, shift] = xs, [y0, y1, dy] = ys;
    for (let x = x0; x <= x1 + 1e-9; x += dx) {
      ctx.beginPath(); ctx.moveTo(X(x), top); ctx.lineTo(X(x), H - bottom); ctx.stroke();
      ctx.fillText(String(x), X(x) - shift, H - bottom + 15);
    }
    for (let y = y0; y <= y1 + 1e-9; y += dy) {
      ctx.beginPath(); ctx.moveTo(left, Y(y)); ctx.lineTo(W - right, Y(y)); ctx.stroke();
      ctx.fillText(String(y), left - 26, Y(y) + 4);
    }
  }

  // --- the root locus in speed, Figure 8 style: Im vs Re of every eigenvalue of the sweep, the
  // colour going from blue (v = 0) to red (v = 10 m/s); the eigenvalues at the speed as rings --
  function drawLocus(canvas, s) {
    const ctx = canvas.getContext("2d"), W = canvas.width, H = canvas.height;
    const left = 56, right = 12, top = 14, bottom = 40;
    const xMin = -15, xMax = 10, yMin = -10, yMax = 10;
    const X = (x) => left + (x - xMin) / (xMax - xMin) * (W - left - right);
    const Y = (y) => top + (yMax - y) / (yMax - yMin) * (H - top - bottom);
    ctx.clearRect(0, 0, W, H);
    ctx.font = "12px sans-serif"; ctx.lineWidth = 1;
    ctx.strokeStyle = "#ddd"; ctx.fillStyle = "#444";
    grid(ctx, { X, Y, left, right, top, bottom, W, H }, [xMin, xMax, 5, 6], [yMin, yMax, 5]);
    ctx.strokeStyle = "#000";
    ctx.beginPath(); ctx.moveTo(X(0), top); ctx.lineTo(X(0), H - bottom); ctx.stroke();
    ctx.beginPath(); ctx.moveTo(left, Y(0)); ctx.lineTo(W - right, Y(0)); ctx.stroke();
    ctx.fillText("Re \u03bb [1/s]", W / 2 - 30, H - 8);
    ctx.save(); ctx.translate(14, H / 2 + 30); ctx.rotate(-Math.PI / 2); ctx.fillText("Im \u03bb [1/s]", 0, 0);
    ctx.restore();
    const inside = (re, im) => re >= xMin && re <= xMax && im >= yMin && im <= yMax;
    const n = s.speeds.length;
    s.speeds.forEach((v, k) => {
      const t = n > 1 ? k / (n - 1) : 0;
      ctx.fillStyle = `rgb(${Math.round(40 + 200 * t)}, 60, ${Math.round(220 - 180 * t)})`;
      for (const [re, im] of s.evs[k]) if (inside(re, im)) ctx.fillRect(X(re) - 1.5, Y(im) - 1.5, 3, 3);
    });
    ctx.strokeStyle = "#e08000"; ctx.lineWidth = 2;
    for (const [re, im] of state.eigenvalues) {
      if (!inside(re, im)) continue;
      ctx.beginPath(); ctx.arc(X(re), Y(im), 5, 0, 2 * Math.PI); ctx.stroke();
    }
  }

  const fmt = (x, digits = 4) => (x === null ? "none in 0\u201310 m/s" : `${x.toFixed(digits)} m/s`);

  function showSpeed(lin) {
    state.eigenvalues = lin.eigenvalues(state.parameters, state.speed);
    $("speed-value").textContent = state.speed.toFixed(2);
    $("eigenvalues").querySelector("tbody").innerHTML = state.eigenvalues
      .map(([re, im]) => `<tr><td>${re.toFixed(4)}</td><td>${im.toFixed(4)}</td></tr>`).join("");
  }

  // Everything that depends on the parameters and the speed, timed.
  function redraw(lin, parametersChanged) {
    const started = performance.now(), evaluations = lin.evaluations;
    if (parametersChanged || !state.sweep) {
      const s = sweep(lin, state.parameters);
      state.sweep = s;
      state.weave = s.weave;
      state.capsize = s.capsize;
      $("weave").textContent = fmt(s.weave);
      $("capsize").textContent = fmt(s.capsize);
    }
    showSpeed(lin);
    draw($("plot"), state.sweep);
    drawLocus($("locus"), state.sweep);
    state.lastRedrawMs = performance.now() - started;
    state.evaluations = lin.evaluations - evaluations;
    state.redraws++;
    $("redraw").textContent = state.lastRedrawMs.toFixed(1);
  }

  // An FMU refusal (FMIError) or another failure of a redraw: shown on the page and kept in
  // cosimApp.error, not thrown into the event loop; the next successful redraw clears it.
  function guarded(action) {
    try {
      action();
      if (state.error !== null) { state.error = null; $("error").textContent = ""; }
    } catch (e) {
      state.error = String(e && e.message ? e.message : e);
      $("error").textContent = `cannot compute the eigenvalues: ${state.error}`;
    }
  }

  function choose(lin, name) {
    state.set = name;
    state.parameters = { ...DATA.parameterSets[name] };
    for (const s of DATA.sliders) {
      $(`slider-${s.name}`).value = String(state.parameters[s.name]);
      $(`value-${s.name}`).textContent = String(Number(state.parameters[s.name].toPrecision(6)));
    }
    redraw(lin, true);
  }

  async function main() {
    $("model").textContent = DATA.model;
    const fmu = await CosimFMU.WasmFMU.fromBytes(DATA.description, base64Bytes(DATA.wasm));
    const lin = new Linearization(fmu);
    const select = $("set");
    for (const name of Object.keys(DATA.parameterSets)) select.add(new Option(name, name));
    const speed = $("speed");
    Object.assign(speed, { min: DATA.speeds.min, max: DATA.speeds.max, step: DATA.speeds.step,
                           value: DATA.speeds.default });
    speed.addEventListener("input", () => guarded(() => { state.speed = Number(speed.value); redraw(lin, false); }));
    const sliders = $("sliders");
    for (const s of DATA.sliders) {
      const label = document.createElement("label");
      label.innerHTML = `${s.label} = <span class="value" id="value-${s.name}"></span> ${s.unit}<br>`;
      const input = document.createElement("input");
      Object.assign(input, { type: "range", id: `slider-${s.name}`, min: s.min, max: s.max, step: s.step });
      input.addEventListener("input", () => guarded(() => {
        state.parameters[s.name] = Number(input.value);
        $(`value-${s.name}`).textContent = input.value;
        redraw(lin, true);
      }));
      label.appendChild(input);
      sliders.appendChild(label);
    }
    select.addEventListener("change", () => guarded(() => choose(lin, select.value)));
    choose(lin, select.value);
    state.ready = true;
  }

  main().catch((e) => {
    state.error = String(e && e.stack ? e.stack : e);
    $("error").textContent = `The app failed: ${e}`;
  });
})();
