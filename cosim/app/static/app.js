// app.js -- the eigenvalue view of `cosim app` (cosim/app/export.py bundles it after its data,
// ml-matrix and fmu.js): eigenvalues vs speed of the bicycles of cosim/app/bicycles.py from the
// WebAssembly FMUs.
//
// A(v) is not computed here: the chosen bicycle's module instance is given the parameters and the
// speed (WhippleLinear: v; the nonlinear Whipple: u_R0 = -v/rR, upright straight running) and
// initialized, and A is the directional derivatives of the lateral states' derivatives with
// respect to the lateral states (COSIM_DATA.bicycles[k].states/derivatives;
// fmi2GetDirectionalDerivative, exact: CasADi's forward mode). By continuation (the default;
// cosimApp.continuation = false turns it off) the instance is reset only when the parameters
// change: it stays in initialization mode and each further speed sets only the speed parameter
// and the guess of the pitch (bicycle.pitch names the state and its guess parameter; the
// nonlinear Whipple solves its pitch by Newton's method from the guess), the pitch solved at the
// previous speed, which is the solution (upright straight running: the pitch depends on the
// geometry, not on the speed); a new geometry starts the iteration from the previous geometry's
// pitch. Without continuation every speed is a new initialization from the module's start values
// (reset, parameters, enter and exit initialization mode). Both give the same numbers: the same
// point, the same directional derivatives. The eigenvalues of A are
// ml-matrix's EigenvalueDecomposition (JAMA's Hessenberg-QR). Weave and capsize speeds are the
// sign changes of the largest real part of the oscillatory / real eigenvalues over the sweep,
// refined by bisection with the same routine, with the definitions of cosim.analytic.whipple
// (forward speeds only; a bicycle ridden backwards gets "self-stable at no speed" or the
// self-stable interval instead).
//
// Parameters come from the sliders (a few) and the parameter editor (every parameter of the
// bicycle, #all-parameters); a value the editor refuses (empty, not a number, outside what the
// parameter allows: cosim.analytic.parameters.validate_parameters' checks, the module's min/max)
// is shown as one message naming the parameter and changes nothing else: the plots stay at the
// last valid parameters. An FMU refusal is shown the same way (cosimApp.error).
//
// window.cosimApp is the page's state for tests: {ready, error, parameterError, bicycle, set
// (= bicycle), module, parameters (the last valid ones, drawn), speed, speedRange {min, max},
// eigenvalues [[re, im] x 4] at the speed, weave, capsize (m/s or null), selfStable ([from, to]
// m/s of the first self-stable run of the sweep, or null), leastUnstable ({speed, re}: the
// smallest largest real part over the sweep), sweep {speeds, evs, modes, weave, capsize}, lastRedrawMs
// [ms: the computation of the last redraw, from its input event's handler to the canvases drawn,
// the browser's paint not included] and evaluations (linearizations) of the last redraw, redraws,
// continuation (true: see above; set it to false to initialize the module anew at every speed),
// clipped {plot, locus}: the points of the sweep that the axes leave out (the plots say so),
// reRange ({min, max} [1/s] chosen, or null: the axes fit), axes {plot, locus} (what a pointer
// position means: the last drawing's margins [CSS px] and limits), hover {plot: {v, eigenvalues,
// modes, text} | null, locus: {v, re, im, mode, text} | null} (the read-outs), rangeError {v, re}
// and viewError (the messages of the range fields and of a refused file or link, or null),
// address (the hash of the view, in the address bar within 250 ms)}.
//
// The side view (sideview.js) is drawn after every redraw; the modes are named by modes.js; the
// view is saved to and loaded from a JSON file and written into the address's hash after every
// redraw (viewstate.js), and a link with such a hash opens that view.
(function () {
  "use strict";
  const DATA = window.COSIM_DATA;
  if (!Array.isArray(DATA.bicycles)) {  // a bundle from an export.py that does not delegate to bicycles.py
    window.cosimApp = { ready: false, error: "COSIM_DATA has no bicycles (cosim.app.bicycles.page_data makes them)" };
    document.getElementById("error").textContent = `The app failed: ${window.cosimApp.error}`;
    return;
  }
  const BICYCLES = new Map(DATA.bicycles.map((b) => [b.name, b]));
  const SLIDERS = new Map(DATA.sliders.map((s) => [s.name, s]));
  const state = { ready: false, error: null, parameterError: null, bicycle: null, set: null, module: null,
                  parameters: {}, speed: DATA.bicycles[0].speeds.default, speedRange: null, eigenvalues: [],
                  weave: null, capsize: null, selfStable: null, leastUnstable: null, sweep: null,
                  lastRedrawMs: null, evaluations: 0, redraws: 0, continuation: true, clipped: null };
  window.cosimApp = state;

  const $ = (id) => document.getElementById(id);
  const base64Bytes = (text) => Uint8Array.from(atob(text), (ch) => ch.charCodeAt(0));

  // Eigenvalues with |Im| below this count as real (as cosim.analytic.whipple._imag_tol).
  const imagTol = (re, im) => 1e-7 * Math.max(1, Math.hypot(re, im));

  // The linearization of one bicycle on its module (one FMU instance per bicycle).
  class Linearization {
    constructor(fmu, bicycle) {
      this.fmu = fmu;
      this.bicycle = bicycle;
      this.instance = fmu.instantiate({ name: bicycle.name });
      this.names = Object.keys(bicycle.parameters);
      this.speed = bicycle.speed;
      this.pitch = bicycle.pitch || null;  // {state, guess} of a module that solves its pitch, else null
      const parameters = [...this.names, this.speed.parameter, ...(this.pitch ? [this.pitch.guess] : [])];
      for (const n of parameters) {
        const v = fmu.variables.get(n);
        if (!v || v.causality !== "parameter") throw new Error(`${fmu.modelName} has no parameter ${n}`);
      }
      if (this.pitch && !fmu.variables.get(this.pitch.state))
        throw new Error(`${fmu.modelName} has no variable ${this.pitch.state}`);
      this.write = this.instance.writer([...this.names, this.speed.parameter]);
      // the speed, and the pitch's guess with it
      this.writeSpeed = this.instance.writer([this.speed.parameter, ...(this.pitch ? [this.pitch.guess] : [])]);
      this.writeGuess = this.pitch ? this.instance.writer([this.pitch.guess]) : null;
      // the derivatives of the lateral states, found by the `derivative` attribute of NAME.json
      const vars = fmu.description.variables;
      const derivativeOf = new Map(vars.filter((v) => v.derivative).map((v) => [vars[v.derivative - 1].name, v.name]));
      const derivatives = bicycle.states.map((s) => {
        if (!derivativeOf.has(s)) throw new Error(`${fmu.modelName} has no state ${s}`);
        return derivativeOf.get(s);
      });
      this.jacobian = this.instance.directional(derivatives, bicycle.states);
      // what a new parameter set is checked by (the evaluation the exit of initialization mode
      // would do), with the solved pitch last
      this.read = this.instance.reader([...derivatives, ...(this.pitch ? [this.pitch.state] : [])]);
      this.initialized = null;  // the parameter values the instance is in initialization mode with
      this.solvedPitch = null;  // [rad] the pitch of the last parameter set, the next one's guess
      this.evaluations = 0;
    }

    // The module's speed parameter for the forward speed v [m/s] (bicycles.SPEED).
    speedValue(p, v) {
      const s = this.speed;
      return s.sign * v / (s.divisor === null ? 1 : p[s.divisor]);
    }

    // A(v) of the parameters p (name -> value): by continuation (state.continuation) from the
    // instance's initialization at the same parameters if it has one, else a new initialization.
    stateMatrix(p, v) {
      const values = this.names.map((n) => p[n]);
      if (!state.continuation) {
        this.initialized = null;
        return this.initializedMatrix(values, v, p);
      }
      try {
        const same = this.initialized !== null && values.every((x, i) => x === this.initialized[i]);
        if (same) {
          this.writeSpeed(this.pitch ? [this.speedValue(p, v), this.solvedPitch] : [this.speedValue(p, v)]);
        } else {
          this.initialized = null;
          const inst = this.instance;
          inst.reset();
          this.write([...values, this.speedValue(p, v)]);
          if (this.solvedPitch !== null) this.writeGuess([this.solvedPitch]);
          inst.setupExperiment({ startTime: 0 });
          inst.enterInitializationMode();
          const read = this.read();  // solves and evaluates now: a refusal is this parameter set's
          if (this.pitch) this.solvedPitch = read[read.length - 1];
          this.initialized = values;
        }
        this.evaluations++;
        return this.jacobian.jacobian();
      } catch (e) {
        this.initialized = null;  // the next call starts anew (reset)
        throw e;
      }
    }

    // A(v) from a new initialization of the instance at the module's start values.
    initializedMatrix(values, v, p) {
      const inst = this.instance;
      inst.reset();
      this.write([...values, this.speedValue(p, v)]);
      inst.setupExperiment({ startTime: 0 });
      inst.enterInitializationMode();
      inst.exitInitializationMode();
      this.evaluations++;
      return this.jacobian.jacobian();
    }

    // The eigenvalues [[re, im], ...] of A(v), sorted by real, then imaginary part; an Error if
    // one is not finite (nothing NaN is drawn).
    eigenvalues(p, v) {
      const e = new mlMatrix.EigenvalueDecomposition(new mlMatrix.Matrix(this.stateMatrix(p, v)));
      const re = e.realEigenvalues, im = e.imaginaryEigenvalues;
      const ev = re.map((r, i) => [r, im[i]]).sort((a, b) => a[0] - b[0] || a[1] - b[1]);
      if (!ev.every(([r, i]) => Number.isFinite(r) && Number.isFinite(i)))
        throw new Error(`${this.fmu.modelName} gives eigenvalues that are not finite at v = ${v} m/s`);
      return ev;
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

  // The first run of sweep speeds where every eigenvalue has a negative real part, its ends
  // refined by bisection (as cosim.analytic.whipple.self_stable_interval), or null; and the
  // speed of the sweep whose largest real part is smallest.
  function stability(lin, p, speeds, evs) {
    const top = evs.map((ev) => Math.max(...ev.map(([re]) => re)));
    let k = 0;
    for (let i = 1; i < top.length; i++) if (top[i] < top[k]) k = i;
    const leastUnstable = { speed: speeds[k], re: top[k] };
    const first = top.findIndex((t) => t < 0);
    if (first < 0) return { selfStable: null, leastUnstable };
    let last = first;
    while (last + 1 < top.length && top[last + 1] < 0) last++;
    const f = (v) => Math.max(...lin.eigenvalues(p, v).map(([re]) => re));
    const from = first === 0 ? speeds[0] : bisect(f, speeds[first - 1], speeds[first], true);
    const to = last === top.length - 1 ? Infinity : bisect(f, speeds[last], speeds[last + 1], false);
    return { selfStable: [from, to], leastUnstable };
  }

  function sweep(lin, p, speedRange) {
    const { min, max, num } = speedRange;
    const speeds = Array.from({ length: num }, (_, k) => min + (max - min) * k / (num - 1));
    speeds[num - 1] = max;
    const evs = speeds.map((v) => lin.eigenvalues(p, v));
    // weave and capsize are defined for riding forwards (cosim.analytic.whipple): a range that
    // also rides backwards (a chosen one) is searched from 0 m/s on
    let critical = { weave: null, capsize: null };
    if (min >= 0) critical = criticalSpeeds(lin, p, speeds, evs);
    else if (max > 0) {
      const ahead = speeds.map((v, k) => k).filter((k) => speeds[k] > 0);
      critical = criticalSpeeds(lin, p, [0, ...ahead.map((k) => speeds[k])],
                                [lin.eigenvalues(p, 0), ...ahead.map((k) => evs[k])]);
    }
    const modes = evs.map((ev, k) => CosimModes.name(ev, speeds[k]));  // weave, capsize, castering (modes.js)
    return { speeds, evs, modes, ...critical, ...stability(lin, p, speeds, evs) };
  }

  // A step of 1, 2 or 5 times a power of ten giving about `count` intervals on [lo, hi].
  function niceStep(lo, hi, count) {
    const raw = (hi - lo) / count, mag = Math.pow(10, Math.floor(Math.log10(raw)));
    return [1, 2, 5, 10].map((m) => m * mag).find((x) => x >= raw * (1 - 1e-9));
  }

  // Axis limits that hold the values, on multiples of a nice step, never narrower than
  // [least, most]; below `floor` (very fast stable modes, which would squash the rest) the axis
  // stops: the caller says on the plot what it leaves out.
  function fitAxis(values, least, most, floor = -Infinity) {
    const all = Math.min(...values), cut = all < 2 * floor ? floor : -Infinity;  // a little beyond: all shown
    let lo = Math.min(least, ...values.filter((x) => x >= cut)), hi = Math.max(most, ...values);
    const step = niceStep(lo, hi, 8);
    return { lo: Math.floor(lo / step - 1e-9) * step, hi: Math.ceil(hi / step + 1e-9) * step, step };
  }

  // The paper's convention (Figure 9): unstable red, stable blue; a real eigenvalue a dot, an
  // oscillatory one a ring.
  const UNSTABLE = "#d02020", STABLE = "#1f4fd0";
  function marker(ctx, x, y, re, oscillatory) {
    ctx.fillStyle = ctx.strokeStyle = re > 0 ? UNSTABLE : STABLE;
    ctx.beginPath();
    if (oscillatory) { ctx.lineWidth = 1.2; ctx.arc(x, y, 2.6, 0, 2 * Math.PI); ctx.stroke(); }
    else { ctx.arc(x, y, 2, 0, 2 * Math.PI); ctx.fill(); }
  }

  // The note on a plot about what its axes leave out ("" if nothing).
  function clipNote(count, what) {
    return count === 0 ? "" : `not shown: ${count} ${what}`;
  }

  // Re lambda of the fast stable modes below this [1/s] is left off the axes when the rest is
  // much smaller (the castor mode reaches -40 1/s at 12 m/s and would flatten the weave and
  // capsize modes the plot is about); the plot says how many points it leaves out.
  const FAST_STABLE = -20;

  // --- the modes named on the plot, the chosen Re range, the axes kept for the read-outs ------
  // [CSS px and data units] of the last drawing of each plot: what a pointer position means
  const axes = { plot: null, locus: null };
  state.axes = axes;

  // The axis of a chosen range {min, max}: exactly that, with a nice step for its grid.
  function chosenAxis(r) {
    return { lo: r.min, hi: r.max, step: niceStep(r.min, r.max, 8) };
  }

  // Each named mode's name beside its curve (the names of CosimModes.name, at each speed): at
  // a point of the curve inside the axes, near a speed of its own so that the names stand apart.
  const MODE_LABELS = [["weave", 0.25], ["capsize", 0.85], ["castering", 0.6], ["capsize + castering", 0.1]];
  function labelModes(ctx, s, X, Y, yMin, yMax, top) {
    const n = s.speeds.length, taken = [];  // the boxes of the names drawn [px]
    ctx.font = "bold 12px sans-serif"; ctx.textBaseline = "bottom"; ctx.lineJoin = "round";
    const W = ctx.canvas.clientWidth;
    const box = (x, y, mode) => {
      const width = ctx.measureText(mode).width, right = x > W - width - 20;
      const x0 = right ? x - 5 - width : x + 5;
      return { x0, x1: x0 + width, y0: y - 18, y1: y - 4, right, tx: right ? x - 5 : x + 5, ty: y - 4 };
    };
    const overlaps = (b) => taken.some((t) => b.x0 < t.x1 && t.x0 < b.x1 && b.y0 < t.y1 && t.y0 < b.y1);
    for (const [mode, at] of MODE_LABELS) {
      let best = null;
      for (let k = 0; k < n; k++) {
        const i = s.modes[k].indexOf(mode);
        if (i < 0) continue;
        const [re, im] = s.evs[k][i];
        if (mode === "weave" && !(Math.abs(im) > imagTol(re, im))) continue;  // named where it is oscillatory
        if (re < yMin || re > yMax || Y(re) < top + 34) continue;  // inside, below the plot's own notes
        const b = box(X(s.speeds[k]), Y(re), mode);
        if (overlaps(b)) continue;
        const d = Math.abs(k / (n - 1) - at);
        if (best === null || d < best.d) best = { d, b };
      }
      if (best === null) continue;
      const b = best.b;
      taken.push(b);
      ctx.textAlign = b.right ? "right" : "left";
      ctx.strokeStyle = "#fff"; ctx.lineWidth = 3; ctx.strokeText(mode, b.tx, b.ty);
      ctx.fillStyle = "#111"; ctx.fillText(mode, b.tx, b.ty);
    }
    ctx.font = "12px sans-serif"; ctx.textAlign = "left"; ctx.textBaseline = "alphabetic"; ctx.lineWidth = 1;
  }

  // --- the plot: real parts vs speed, Figure 9 of the paper: unstable red, stable blue, real
  // modes dots, oscillatory rings; |Im| grey; the axes fit the eigenvalues ------------------
  function draw(canvas, s) {
    const { ctx, W, H } = CosimCanvas.fit(canvas, 600, 400);
    const left = 56, right = 12, top = 14, bottom = 40;
    const { min, max } = state.speedRange;
    const res = s.evs.flat().map(([re]) => re);
    const ims = s.evs.flat().filter(([re, im]) => Math.abs(im) > imagTol(re, im)).map(([, im]) => Math.abs(im));
    const ax = state.reRange ? chosenAxis(state.reRange) : fitAxis([...res, ...ims], -5, 5, FAST_STABLE);
    const yMin = ax.lo, yMax = ax.hi;
    axes.plot = { left, right, top, bottom, W, H, min, max, yMin, yMax };
    const X = (v) => left + (v - min) / (max - min) * (W - left - right);
    const Y = (y) => top + (yMax - y) / (yMax - yMin) * (H - top - bottom);
    ctx.clearRect(0, 0, W, H);
    ctx.font = "12px sans-serif"; ctx.textAlign = "left"; ctx.textBaseline = "alphabetic";
    ctx.strokeStyle = "#ddd"; ctx.fillStyle = "#444"; ctx.lineWidth = 1;
    const xStep = niceStep(min, max, Math.max(3, Math.floor((W - left - right) / 70)));
    grid(ctx, { X, Y, left, right, top, bottom, W, H }, [min, max, xStep, 4], [yMin, yMax, ax.step]);
    ctx.strokeStyle = "#000";
    if (yMin <= 0 && 0 <= yMax) { ctx.beginPath(); ctx.moveTo(left, Y(0)); ctx.lineTo(W - right, Y(0)); ctx.stroke(); }
    ctx.fillText("speed v [m/s]", W / 2 - 40, H - 8);
    ctx.save(); ctx.translate(14, H / 2 + 60); ctx.rotate(-Math.PI / 2);
    ctx.fillText("Re \u03bb, |Im \u03bb| (grey) [1/s]", 0, 0); ctx.restore();
    if (s.selfStable !== null) {  // the self-stable band
      ctx.fillStyle = "rgba(60, 170, 60, 0.14)";
      const [a, b] = s.selfStable, end = Math.min(b, max);
      ctx.fillRect(X(a), top, X(end) - X(a), H - top - bottom);
    }
    let clipped = 0;
    s.speeds.forEach((v, k) => {
      for (const [re, im] of s.evs[k]) {
        const osc = Math.abs(im) > imagTol(re, im);
        if (osc && Math.abs(im) <= yMax) { ctx.fillStyle = "#aaa"; ctx.fillRect(X(v) - 1, Y(Math.abs(im)) - 1, 2, 2); }
      }
    });
    s.speeds.forEach((v, k) => {
      for (const [re, im] of s.evs[k]) {
        if (re < yMin || re > yMax) { clipped++; continue; }
        marker(ctx, X(v), Y(re), re, Math.abs(im) > imagTol(re, im));
      }
    });
    if (max > 0) labelModes(ctx, s, X, Y, yMin, yMax, top);  // riding backwards: not named (modes.js)
    ctx.strokeStyle = "#e08000"; ctx.lineWidth = 1.5;
    ctx.beginPath(); ctx.moveTo(X(state.speed), top); ctx.lineTo(X(state.speed), H - bottom); ctx.stroke();
    const note = clipNote(clipped, state.reRange ? `points outside Re \u03bb ${yMin} to ${yMax} 1/s (the range chosen)`
      : `points below ${yMin} 1/s (down to ${Math.min(...res).toFixed(1)})`);
    state.clipped = { plot: clipped, locus: state.clipped ? state.clipped.locus : 0 };
    if (note) { ctx.fillStyle = "#444"; ctx.fillText(`\u25bc ${note}`, left + 6, top + 12); }
  }

  // Grid lines with their labels: xs = [first, last, step, label offset], ys = [first, last, step]
  // (the stroke and fill styles are the caller's).
  function grid(ctx, { X, Y, left, right, top, bottom, W, H }, xs, ys) {
    const [x0, x1, dx, shift] = xs, [y0, y1, dy] = ys;
    const label = (x) => String(Math.round(x * 1e6) / 1e6);
    for (let x = Math.ceil(x0 / dx - 1e-9) * dx; x <= x1 + 1e-9; x += dx) {
      ctx.beginPath(); ctx.moveTo(X(x), top); ctx.lineTo(X(x), H - bottom); ctx.stroke();
      ctx.fillText(label(x), X(x) - shift, H - bottom + 15);
    }
    for (let y = Math.ceil(y0 / dy - 1e-9) * dy; y <= y1 + 1e-9; y += dy) {  // a chosen range: its multiples of dy
      ctx.beginPath(); ctx.moveTo(left, Y(y)); ctx.lineTo(W - right, Y(y)); ctx.stroke();
      ctx.fillText(label(y), left - 30, Y(y) + 4);
    }
  }

  // --- the root locus in speed, Figure 8 of the paper: Im vs Re of every eigenvalue of the
  // sweep, unstable red, stable blue, real dots, oscillatory rings; the eigenvalues at the lowest
  // speed black squares, at the chosen speed orange rings; the axes fit the eigenvalues ---------
  function drawLocus(canvas, s) {
    const { ctx, W, H } = CosimCanvas.fit(canvas, 600, 400);
    const left = 56, right = 12, top = 14, bottom = 40;
    const all = s.evs.flat();
    const xa = state.reRange ? chosenAxis(state.reRange) : fitAxis(all.map(([re]) => re), -5, 5, FAST_STABLE);
    const imMax = Math.max(5, ...all.map(([, im]) => Math.abs(im)));
    const ya = fitAxis([imMax, -imMax], -5, 5);
    const xMin = xa.lo, xMax = xa.hi, yMin = ya.lo, yMax = ya.hi;
    const X = (x) => left + (x - xMin) / (xMax - xMin) * (W - left - right);
    const Y = (y) => top + (yMax - y) / (yMax - yMin) * (H - top - bottom);
    axes.locus = { X, Y, left, right, top, bottom, W, H, xMin, xMax, yMin, yMax };
    ctx.clearRect(0, 0, W, H);
    ctx.font = "12px sans-serif"; ctx.textAlign = "left"; ctx.textBaseline = "alphabetic"; ctx.lineWidth = 1;
    ctx.strokeStyle = "#ddd"; ctx.fillStyle = "#444";
    grid(ctx, { X, Y, left, right, top, bottom, W, H }, [xMin, xMax, xa.step, 6], [yMin, yMax, ya.step]);
    ctx.strokeStyle = "#000";
    if (xMin <= 0 && 0 <= xMax) { ctx.beginPath(); ctx.moveTo(X(0), top); ctx.lineTo(X(0), H - bottom); ctx.stroke(); }
    ctx.beginPath(); ctx.moveTo(left, Y(0)); ctx.lineTo(W - right, Y(0)); ctx.stroke();
    ctx.fillText("Re \u03bb [1/s]", W / 2 - 30, H - 8);
    ctx.save(); ctx.translate(14, H / 2 + 30); ctx.rotate(-Math.PI / 2); ctx.fillText("Im \u03bb [1/s]", 0, 0);
    ctx.restore();
    const inside = (re) => re >= xMin && re <= xMax;
    let clipped = 0;
    s.speeds.forEach((v, k) => {
      for (const [re, im] of s.evs[k]) {
        if (!inside(re)) { clipped++; continue; }
        marker(ctx, X(re), Y(im), re, Math.abs(im) > imagTol(re, im));
      }
    });
    ctx.fillStyle = "#000";
    for (const [re, im] of s.evs[0]) if (inside(re)) ctx.fillRect(X(re) - 3.5, Y(im) - 3.5, 7, 7);
    ctx.strokeStyle = "#e08000"; ctx.lineWidth = 2;
    for (const [re, im] of state.eigenvalues) {
      if (!inside(re)) continue;
      ctx.beginPath(); ctx.arc(X(re), Y(im), 6, 0, 2 * Math.PI); ctx.stroke();
    }
    const { min, max } = state.speedRange;
    ctx.fillStyle = "#444";
    ctx.fillText(`v from ${min} (black squares) to ${max} m/s`, left + 6, top + 12);
    const note = clipNote(clipped, state.reRange ? `points outside Re \u03bb ${xMin} to ${xMax} 1/s (the range chosen)`
      : `points left of Re \u03bb = ${xMin} 1/s`);
    state.clipped = { plot: state.clipped ? state.clipped.plot : 0, locus: clipped };
    if (note) ctx.fillText(`\u25c0 ${note}`, left + 6, top + 26);
  }

  const range = () => `${state.speedRange.min}\u2013${state.speedRange.max} m/s`;
  // Speeds are printed with the decimals of cosim.app.bicycles.SPEED_DIGITS (tests compare them with
  // cosim.analytic to these digits).
  const DIGITS = DATA.speedDigits || 3;
  const forward = () => `${Math.max(0, state.speedRange.min)}\u2013${state.speedRange.max} m/s`;
  const fmt = (x, digits = DIGITS) => (x === null ? `none in ${forward()}` : `${x.toFixed(digits)} m/s`);

  // Weave and capsize speeds (of the forward speeds of the range), or (riding backwards only)
  // "not defined", and where the bicycle is self-stable.
  function showStability(s) {
    if (state.speedRange.max > 0) {
      $("weave").textContent = fmt(s.weave);
      $("capsize").textContent = fmt(s.capsize);
    } else {
      $("weave").textContent = "not defined riding backwards";
      $("capsize").textContent = "not defined riding backwards";
    }
    const u = s.leastUnstable;
    $("self-stable").textContent = s.selfStable !== null
      ? `self-stable from ${s.selfStable[0].toFixed(DIGITS)} to ${s.selfStable[1] === Infinity
        ? `beyond ${state.speedRange.max}` : s.selfStable[1].toFixed(DIGITS)} m/s`
      : `self-stable at no speed of ${range()}: the largest real part is at least ${u.re.toFixed(3)} 1/s ` +
        `(at v = ${u.speed.toFixed(2)} m/s; p\u03c4 = ${(u.re * 0.2).toFixed(2)} for a rider's delay \u03c4 = 0.2 s)`;
  }

  function showSpeed(lin, p) {
    const ev = lin.eigenvalues(p, state.speed);
    state.eigenvalues = ev;
    $("speed-value").textContent = state.speed.toFixed(2);
    $("eigenvalues").querySelector("tbody").innerHTML = ev
      .map(([re, im]) => `<tr><td>${re.toFixed(4)}</td><td>${im.toFixed(4)}</td></tr>`).join("");
  }

  // Everything that depends on the parameters and the speed, timed. `p` is the new parameter
  // set (computed first; state.parameters becomes p only if every linearization succeeded).
  function redraw(lin, p) {
    const started = performance.now(), evaluations = lin.evaluations;
    if (p !== undefined || !state.sweep) {
      p = p === undefined ? state.parameters : p;
      const s = sweep(lin, p, state.speedRange);  // a failure here leaves everything as it was
      state.parameters = p;
      state.sweep = s;
      state.weave = s.weave;
      state.capsize = s.capsize;
      state.selfStable = s.selfStable;
      state.leastUnstable = s.leastUnstable;
      showStability(s);
    }
    showSpeed(lin, state.parameters);
    draw($("plot"), state.sweep);
    drawLocus($("locus"), state.sweep);
    state.lastRedrawMs = performance.now() - started;
    state.evaluations = lin.evaluations - evaluations;
    state.redraws++;
    $("redraw").textContent = state.lastRedrawMs.toFixed(1);
    viewRedrawn();
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

  // --- parameter checks (the editor): cosim.analytic.parameters.validate_parameters' rules and
  // messages ("<key>: <why> (got <key> = <value> <unit>)"), with the checks the bicycle's set
  // waives (bicycle.waived), and the module's declared min/max --------------------------------
  const NUMBER = /^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/;
  const REL_TOL = 1e-12;

  function unitOf(fmu, name) { const v = fmu.variables.get(name); return (v && v.unit) || ""; }

  // The first problem of the parameter set p as one message, or null.
  function problem(fmu, bicycle, p) {
    const waived = new Set(bicycle.waived);
    const got = (k) => `(got ${k} = ${p[k]} ${unitOf(fmu, k)})`;
    const fail = (k, why) => `${k}: ${why} ${got(k)}`;
    const has = (k) => k in p;
    for (const k of ["w", "rR", "rF", "g"]) if (has(k) && !(p[k] > 0)) return fail(k, "must be positive");
    if (has("c") && !(Math.abs(p.c) < p.w)) return fail("c", "trail must satisfy |c| < w (wheelbase)");
    if (has("lam") && !(-Math.PI / 2 < p.lam && p.lam < Math.PI / 2))
      return fail("lam", "steer-axis tilt must lie in (-pi/2, pi/2) rad");
    for (const k of ["mR", "mB", "mH", "mF"]) if (has(k) && p[k] < 0) return fail(k, "mass must be non-negative");
    if (has("mH") && p.mH + p.mF <= 0) return fail("mH", "front assembly mass mH + mF must be positive");
    for (const k of ["zB", "zH"])
      if (has(k) && !(p[k] < 0)) return fail(k, "centre of mass must be above the ground (z points down, so z < 0)");
    for (const w of ["R", "F"]) {
      const ixx = `I${w}xx`, iyy = `I${w}yy`;
      for (const k of [ixx, iyy]) if (p[k] < 0) return fail(k, "moment of inertia must be non-negative");
      if (!waived.has(iyy) && p[iyy] > 2 * p[ixx] * (1 + REL_TOL))
        return fail(iyy, `triangle inequality violated: ${iyy} <= 2 ${ixx} = ${2 * p[ixx]} required for an axisymmetric wheel`);
    }
    for (const b of ["B", "H"]) {
      const [ixx, ixz, iyy, izz] = ["xx", "xz", "yy", "zz"].map((s) => `I${b}${s}`);
      for (const k of [ixx, iyy, izz]) if (p[k] < 0) return fail(k, "moment of inertia must be non-negative");
      const scale = Math.max(p[ixx], p[izz], p[iyy], Math.abs(p[ixz]));
      if (p[ixx] * p[izz] - p[ixz] ** 2 < -REL_TOL * scale ** 2)
        return fail(ixz, `inertia tensor not positive semidefinite: ${ixz}**2 <= ${ixx}*${izz} = ${p[ixx] * p[izz]} required`);
      if (waived.has(iyy)) continue;
      if (p[iyy] > (p[ixx] + p[izz]) * (1 + REL_TOL))
        return fail(iyy, `triangle inequality of principal moments violated: ${iyy} <= ${ixx} + ${izz} = ${p[ixx] + p[izz]} required`);
      const spread = Math.hypot(p[ixx] - p[izz], 2 * p[ixz]);
      if (spread > p[iyy] * (1 + REL_TOL) + REL_TOL * scale)
        return fail(iyy, `triangle inequality of principal moments violated: ${iyy} >= sqrt((${ixx}-${izz})**2 + 4 ${ixz}**2) = ${spread} required`);
    }
    for (const k of Object.keys(p)) {  // what the module declares (e.g. the crown radii tR, tF >= 0)
      const v = fmu.variables.get(k);
      if (v && v.min !== undefined && p[k] < v.min) return fail(k, `must be >= ${v.min} (the module's minimum)`);
      if (v && v.max !== undefined && p[k] > v.max) return fail(k, `must be <= ${v.max} (the module's maximum)`);
    }
    return null;
  }

  // The editor's values as numbers, or the message about the first that is not one.
  function parseEditor(bicycle) {
    const p = {};
    for (const name of Object.keys(bicycle.parameters)) {
      const text = $(`param-${name}`).value.trim();
      if (text === "") return { message: `${name}: empty; type a number` };
      if (!NUMBER.test(text)) return { message: `${name}: not a number: '${text}'` };
      p[name] = Number(text);
      if (!Number.isFinite(p[name])) return { message: `${name}: must be finite, got '${text}'` };
    }
    return { parameters: p };
  }

  function showParameterError(message) {
    state.parameterError = message;
    $("parameter-error").textContent = message === null ? "" : `not used: ${message}; the plots show the last valid parameters`;
  }

  // --- the page ----------------------------------------------------------------------------
  const app = { fmus: new Map(), lins: new Map() };

  // Every module a bicycle uses, compiled once at load (a choice is then synchronous).
  async function loadModules() {
    for (const name of new Set(DATA.bicycles.map((b) => b.module))) {
      const m = DATA.modules[name];
      if (!m) throw new Error(`the page carries no module ${name}`);
      app.fmus.set(name, await CosimFMU.WasmFMU.fromBytes(m.description, base64Bytes(m.wasm)));
    }
  }

  const linearization = () => app.lins.get(state.bicycle);
  const shown = (x) => String(Number(x.toPrecision(6)));

  function syncControls(bicycle) {
    for (const s of DATA.sliders) {
      const label = $(`slider-${s.name}`).parentElement;
      label.style.display = bicycle.sliders.includes(s.name) ? "" : "none";
      if (s.name in state.parameters) {
        $(`slider-${s.name}`).value = String(state.parameters[s.name]);
        $(`value-${s.name}`).textContent = shown(state.parameters[s.name]);
      }
    }
    for (const name of Object.keys(bicycle.parameters)) $(`param-${name}`).value = String(state.parameters[name]);
  }

  // The editor of every parameter of the bicycle: one number field each, unit and description
  // from the module's NAME.json.
  function buildEditor(fmu, bicycle) {
    let box = $("all-parameters");
    if (!box) {  // index.html without the container: made here, after the sliders
      box = document.createElement("div");
      box.id = "all-parameters";
      $("sliders").after(box);
    }
    box.innerHTML = "";
    const details = document.createElement("details");
    details.innerHTML = `<summary>all parameters of ${bicycle.name} (${fmu.modelName})</summary>` +
      `<div id="parameter-error" style="color:#b00"></div>`;
    const table = document.createElement("table");
    table.style.fontSize = "0.85em";
    for (const name of Object.keys(bicycle.parameters)) {
      const v = fmu.variables.get(name), row = table.insertRow();
      row.title = v.description || "";
      row.insertCell().innerHTML = `<label for="param-${name}">${name}</label>`;
      const input = document.createElement("input");
      Object.assign(input, { type: "text", id: `param-${name}`, size: 9, inputMode: "decimal" });
      input.setAttribute("aria-label", `${name} [${v.unit || "1"}]: ${v.description || ""}`);
      input.addEventListener("input", () => editorInput(fmu, bicycle));
      row.insertCell().appendChild(input);
      row.insertCell().textContent = v.unit || "";
      const d = row.insertCell();  // one line, the whole text on hover (the column is narrow)
      d.textContent = v.description || "";
      Object.assign(d.style, { textAlign: "left", fontSize: "0.8em", whiteSpace: "nowrap", overflow: "hidden",
                               textOverflow: "ellipsis", maxWidth: "150px" });
    }
    details.appendChild(table);
    box.appendChild(details);
  }

  function editorInput(fmu, bicycle) {
    const parsed = parseEditor(bicycle);
    const message = parsed.message || problem(fmu, bicycle, parsed.parameters);
    if (message) { showParameterError(message); return; }
    showParameterError(null);
    guarded(() => {
      redraw(linearization(), parsed.parameters);
      for (const s of DATA.sliders) if (s.name in state.parameters) {
        $(`slider-${s.name}`).value = String(state.parameters[s.name]);
        $(`value-${s.name}`).textContent = shown(state.parameters[s.name]);
      }
    });
  }

  function sliderInput(s, input) {
    const bicycle = BICYCLES.get(state.bicycle), fmu = app.fmus.get(bicycle.module);
    const p = { ...state.parameters, [s.name]: Number(input.value) };
    const message = problem(fmu, bicycle, p);
    $(`value-${s.name}`).textContent = input.value;
    if (message) { showParameterError(message); return; }
    guarded(() => {
      redraw(linearization(), p);
      showParameterError(null);  // the editor shows the parameters drawn (a refused text there is gone)
      for (const name of Object.keys(bicycle.parameters)) $(`param-${name}`).value = String(state.parameters[name]);
    });
  }

  function choose(name) {
    const bicycle = BICYCLES.get(name);
    const fmu = app.fmus.get(bicycle.module);
    if (!app.lins.has(name)) app.lins.set(name, new Linearization(fmu, bicycle));
    state.bicycle = state.set = name;
    state.module = bicycle.module;
    state.speedRange = { min: bicycle.speeds.min, max: bicycle.speeds.max, num: bicycle.speeds.num };
    state.reRange = null;
    showRanges();
    $("model").textContent = bicycle.module;
    $("bicycle-explanation").textContent = bicycle.explanation;
    const speed = $("speed");
    Object.assign(speed, { min: bicycle.speeds.min, max: bicycle.speeds.max, step: bicycle.speeds.step });
    if (!(state.speed >= bicycle.speeds.min && state.speed <= bicycle.speeds.max)) state.speed = bicycle.speeds.default;
    speed.value = String(state.speed);
    state.parameters = { ...bicycle.parameters };
    state.sweep = null;
    buildEditor(fmu, bicycle);
    showParameterError(null);
    syncControls(bicycle);
    guarded(() => redraw(app.lins.get(name), { ...bicycle.parameters }));
  }

  // --- the side view, the chosen ranges, the read-outs, save / load / the address -------------
  // (sideview.js draws, modes.js names, viewstate.js reads and writes; applied here)

  // After every redraw: the side view of the parameters drawn, the read-out of the plot at its
  // speed computed anew, the address set to the view.
  function viewRedrawn() {
    CosimSideView.draw($("geometry"), state.parameters);
    if (state.hover.locus !== null) { state.hover.locus = null; $("locus-readout").textContent = LOCUS_HINT; }
    if (state.hover.plot !== null) {  // its speed may lie outside a new range
      const v = state.hover.plot.v;
      if (v >= state.speedRange.min && v <= state.speedRange.max) plotReadout(v);
      else { state.hover.plot = null; $("plot-readout").textContent = PLOT_HINT; drawPlots(); }
    }
    writeAddress();
  }

  const PLOT_HINT = "point at the plot (or tap it, or press Tab to it and use \u2190 \u2192) for the eigenvalues at that speed";
  const LOCUS_HINT = "point at the root locus (or tap it) for the nearest eigenvalue and its speed";
  const speedText = (v) => `v = ${v.toFixed(2)} m/s`;

  // The eigenvalues at the speed v [m/s] (rounded to the speed slider's 0.01 m/s), named.
  function plotReadout(v) {
    const ev = linearization().eigenvalues(state.parameters, v);
    const text = `${speedText(v)}: ${CosimModes.readout(ev, v)} (1/s)`;
    state.hover.plot = { v, eigenvalues: ev, modes: CosimModes.name(ev, v), text };
    $("plot-readout").textContent = text;
    drawPlots();
  }

  // Both plots, with what the pointer reads out marked: a dashed line at its speed on the plot,
  // a black ring around its eigenvalue on the root locus.
  function drawPlots() {
    if (!state.sweep) return;
    draw($("plot"), state.sweep);
    drawLocus($("locus"), state.sweep);
    const h = state.hover, dpr = window.devicePixelRatio || 1;
    if (h.plot !== null && axes.plot) {
      const a = axes.plot, ctx = $("plot").getContext("2d");
      const x = a.left + (h.plot.v - a.min) / (a.max - a.min) * (a.W - a.left - a.right);
      ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
      ctx.strokeStyle = "#333"; ctx.lineWidth = 1; ctx.setLineDash([4, 3]);
      ctx.beginPath(); ctx.moveTo(x, a.top); ctx.lineTo(x, a.H - a.bottom); ctx.stroke(); ctx.setLineDash([]);
    }
    if (h.locus !== null && axes.locus) {
      const a = axes.locus, ctx = $("locus").getContext("2d");
      ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
      ctx.strokeStyle = "#000"; ctx.lineWidth = 2;
      ctx.beginPath(); ctx.arc(a.X(h.locus.re), a.Y(h.locus.im), 8, 0, 2 * Math.PI); ctx.stroke();
    }
  }

  function plotPointer(event) {
    const a = axes.plot;
    if (!a || !state.sweep) return;
    const f = (event.offsetX - a.left) / (a.W - a.left - a.right);
    if (!(f >= -0.02 && f <= 1.02)) return;
    const v = Math.min(a.max, Math.max(a.min, Number((a.min + f * (a.max - a.min)).toFixed(2))));
    guarded(() => plotReadout(v));
  }

  // The keyboard's read-out of the focused plot: arrows move its speed by 0.1 m/s (with Shift 1 m/s)
  // from the speed read out last (else the chosen one), Home and End go to the ends of the range.
  function plotKey(event) {
    const a = axes.plot;
    if (!a || !state.sweep) return;
    const from = state.hover.plot !== null ? state.hover.plot.v : state.speed, step = event.shiftKey ? 1 : 0.1;
    const to = { ArrowRight: from + step, ArrowUp: from + step, ArrowLeft: from - step, ArrowDown: from - step,
                 Home: a.min, End: a.max }[event.key];
    if (to === undefined) return;
    event.preventDefault();  // (the arrows would scroll the page)
    const v = Math.min(a.max, Math.max(a.min, Number(to.toFixed(2))));
    guarded(() => plotReadout(v));
  }

  // The eigenvalue of the sweep nearest the pointer on the root locus, its speed and mode.
  function locusPointer(event) {
    const a = axes.locus, s = state.sweep;
    if (!a || !s) return;
    let best = null;
    s.evs.forEach((ev, k) => ev.forEach(([re, im], i) => {
      const d = Math.hypot(a.X(re) - event.offsetX, a.Y(im) - event.offsetY);
      if (best === null || d < best.d) best = { d, k, i, re, im };
    }));
    const v = s.speeds[best.k], mode = s.modes[best.k][best.i];
    const text = `\u03bb = ${CosimModes.value(best.re, best.im)} 1/s at ${speedText(v)}: ` +
      (mode || (v < 0 ? "modes not named riding backwards" : "not named"));
    state.hover.locus = { v, re: best.re, im: best.im, mode, text };
    $("locus-readout").textContent = text;
    drawPlots();
  }

  // The range fields show the ranges of the view; their messages cleared.
  function showRanges() {
    const r = state.speedRange;
    $("v-min").value = String(r.min); $("v-max").value = String(r.max);
    $("re-min").value = state.reRange ? String(state.reRange.min) : "";
    $("re-max").value = state.reRange ? String(state.reRange.max) : "";
    $("v-range-error").textContent = $("re-range-error").textContent = "";
    state.rangeError = { v: null, re: null };
  }

  // A speed range [m/s] for the view: the slider's ends, the speed kept inside.
  function setSpeedRange(r) {
    const bicycle = BICYCLES.get(state.bicycle);
    state.speedRange = { min: r.min, max: r.max, num: bicycle.speeds.num };
    const speed = $("speed");
    Object.assign(speed, { min: r.min, max: r.max });
    state.speed = Math.min(r.max, Math.max(r.min, state.speed));
    speed.value = String(state.speed);
  }

  // A change of a range field: applied (the sweep recomputed for a new speed range, only redrawn
  // for a new Re range) or its message beside the field, the plots as they were.
  function rangeInput(which) {
    const [lo, hi, out] = which === "v" ? ["v-min", "v-max", "v-range-error"] : ["re-min", "re-max", "re-range-error"];
    const parsed = CosimViewState.range($(lo).value, $(hi).value, which === "re");
    const message = parsed.message ? `${which === "v" ? "speed" : "Re \u03bb"} range ${parsed.message}` : null;
    state.rangeError[which] = message;
    $(out).textContent = message === null ? "" : `${message}; the plots keep the last valid range`;
    if (parsed.message) return;
    if (which === "re") { state.reRange = parsed.range; guarded(() => redraw(linearization())); return; }
    const previous = { ...state.speedRange }, speed = state.speed;
    setSpeedRange(parsed.range);
    guarded(() => redraw(linearization(), state.parameters));
    if (state.error !== null) {  // the module refused a speed of the range: the previous range back
      const refused = state.error;
      setSpeedRange(previous); state.speed = speed; $("speed").value = String(speed);
      guarded(() => redraw(linearization(), state.parameters));
      showRanges();
      state.rangeError.v = `speed range ${parsed.range.min} to ${parsed.range.max} m/s: ${refused}`;
      $(out).textContent = `${state.rangeError.v}; the plots keep the last valid range`;
    }
  }

  const currentView = () => ({ bicycle: state.bicycle, parameters: { ...state.parameters }, speed: state.speed,
                               speedRange: { min: state.speedRange.min, max: state.speedRange.max },
                               reRange: state.reRange ? { ...state.reRange } : null });

  // The address (its hash) always holds the view: a link to it restores it (readAddress). It is
  // written at most every ADDRESS_MS, the last view of a burst (a dragged slider) after it:
  // browsers ignore history.replaceState called hundreds of times in a few seconds.
  const ADDRESS_MS = 250;
  let written = null, pending = null, lastWrite = -Infinity;
  function writeAddress() {
    if (!state.ready && !state.addressRead) return;  // a shared address is read before it is overwritten
    state.address = CosimViewState.toHash(currentView(), DATA.bicycles);
    if (pending !== null) return;  // the timer writes the latest
    const wait = lastWrite + ADDRESS_MS - performance.now();
    if (wait <= 0) flushAddress(); else pending = setTimeout(flushAddress, wait);
  }

  function flushAddress() {
    pending = null;
    lastWrite = performance.now();
    written = state.address;
    if (location.hash.replace(/^#/, "") === written) return;
    try { history.replaceState(null, "", `#${written}`); } catch (e) { location.replace(`#${written}`); }
  }

  function showViewError(message) {
    state.viewError = message;
    $("view-error").textContent = message === null ? "" : message;
  }

  // A view (CosimViewState's, checked there) applied: its bicycle, ranges, parameters (the
  // editor's checks first: a refused parameter refuses the view) and speed. Returns the problem
  // or null.
  function applyView(view) {
    const bicycle = BICYCLES.get(view.bicycle), fmu = app.fmus.get(bicycle.module);
    const message = problem(fmu, bicycle, view.parameters);
    if (message) return `parameters.${message}`;
    const before = currentView();
    if (state.bicycle !== view.bicycle) { $("set").value = view.bicycle; choose(view.bicycle); }
    state.speed = view.speed;
    setSpeedRange(view.speedRange);
    state.reRange = view.reRange;
    showRanges();
    guarded(() => redraw(linearization(), { ...view.parameters }));
    if (state.error !== null) {  // the FMU refused: the previous view back
      const e = state.error;
      if (before.bicycle !== state.bicycle) { $("set").value = before.bicycle; choose(before.bicycle); }
      state.speed = before.speed; setSpeedRange(before.speedRange); state.reRange = before.reRange; showRanges();
      guarded(() => redraw(linearization(), before.parameters));
      syncControls(BICYCLES.get(state.bicycle));
      return e;
    }
    syncControls(bicycle);
    showParameterError(null);
    return null;
  }

  function readAddress() {
    const got = CosimViewState.fromHash(location.hash, DATA.bicycles);
    state.addressRead = true;
    if (got === null) return;
    const message = got.message || applyView(got.view);
    showViewError(message ? `the link was not applied: ${message}` : null);
  }

  function saveView() {
    const a = document.createElement("a");
    a.href = URL.createObjectURL(new Blob([CosimViewState.toFile(currentView())], { type: "application/json" }));
    a.download = `cosim-bicycle-${state.bicycle}.json`;
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 60_000);
  }

  async function loadView(input) {
    const file = input.files && input.files[0];
    if (!file) return;
    const got = CosimViewState.fromFile(await file.text(), DATA.bicycles);
    const message = got.message || applyView(got.view);
    showViewError(message ? `${file.name} was not loaded: ${message}` : null);
    input.value = "";  // the same file can be loaded again
  }

  function setupView() {
    Object.assign(state, { hover: { plot: null, locus: null }, reRange: null, rangeError: { v: null, re: null }, viewError: null,
                           addressRead: false });
    $("plot-readout").textContent = PLOT_HINT;
    $("locus-readout").textContent = LOCUS_HINT;
    for (const [id, handler] of [["plot", plotPointer], ["locus", locusPointer]]) {
      $(id).addEventListener("pointermove", handler);
      $(id).addEventListener("pointerdown", handler);
    }
    $("plot").addEventListener("keydown", plotKey);
    for (const id of ["v-min", "v-max"]) $(id).addEventListener("change", () => rangeInput("v"));
    for (const id of ["re-min", "re-max"]) $(id).addEventListener("change", () => rangeInput("re"));
    $("view-save").addEventListener("click", saveView);
    $("view-load").addEventListener("change", (e) => loadView(e.target).catch((err) => showViewError(String(err))));
    window.addEventListener("hashchange", () => {
      if (location.hash.replace(/^#/, "") !== written) guarded(readAddress);
    });
  }

  async function main() {
    setupView();
    const select = $("set");
    for (const b of DATA.bicycles) select.add(new Option(b.label, b.name));
    // the explanation folded (a long one would push the plot off a phone's screen)
    const about = document.createElement("details");
    about.id = "bicycle-about";
    about.className = "caption";
    about.innerHTML = '<summary>about this bicycle</summary><p id="bicycle-explanation" class="note"></p>';
    select.parentElement.after(about);
    const stable = document.createElement("p");
    stable.id = "self-stable";
    stable.className = "note";
    $("weave").parentElement.after(stable);
    const speed = $("speed");
    speed.addEventListener("input", () => guarded(() => {
      state.speed = Number(speed.value);
      redraw(linearization());
    }));
    const sliders = $("sliders");
    for (const s of DATA.sliders) {
      const label = document.createElement("label");
      label.innerHTML = `${s.label} = <span class="value" id="value-${s.name}"></span> ${s.unit}<br>`;
      const input = document.createElement("input");
      Object.assign(input, { type: "range", id: `slider-${s.name}`, min: s.min, max: s.max, step: s.step });
      input.addEventListener("input", () => sliderInput(s, input));
      label.appendChild(input);
      sliders.appendChild(label);
    }
    select.addEventListener("change", () => guarded(() => choose(select.value)));
    // a new window size or pixel ratio (zoom, another screen): the plots drawn again, not recomputed
    window.addEventListener("resize", () => guarded(() => {
      drawPlots();
      CosimSideView.draw($("geometry"), state.parameters);
    }));
    await loadModules();
    choose(select.value);
    if (state.error !== null) throw new Error(state.error);
    readAddress();  // a shared link: its view
    state.ready = true;
    writeAddress();
  }

  main().catch((e) => {
    state.error = String(e && e.stack ? e.stack : e);
    $("error").textContent = `The app failed: ${e}`;
  });
})();
