// ride.js -- the rides of `cosim app` (cosim/app/export.py bundles it after fmu.js, three.js,
// ride3d.js and plots.js): the nonlinear Whipple bicycle's WebAssembly FMU run by a small
// co-simulation master in the page, played in the 3-D view (CosimRide3D) with plots (CosimPlots)
// and a CSV download; the guided demos (COSIM_DATA.demos, from cosim/app/demos/*.toml); the rider
// in the loop (keyboard / gamepad / on-screen touch buttons: a torque through an adjustable delay,
// in real time or in slow motion, with a goal and its verdict in plain words). Without WebGL the
// rides are drawn in 2-D (CosimRide2D of ride2d.js) with a plain message.
//
// The bicycle's equations are never written here: every step is the FMU's fmi2DoStep (the module
// compiled from its own C sources). Controllers are the library's Modelica blocks compiled to
// WebAssembly too (Bicycle.Control.PD, Bicycle.Control.LaneChange); the page only wires signals:
//
//   at each communication point t_k = k*h (h = 0.01 s):
//     y = the bicycle's outputs at t_k (recorded; |phi| > 1 rad ends the ride: a fall)
//     controller inputs <- y; T = the controller's output at t_k
//     bicycle input = source(t_k) + delayed T (+ keyboard, delayed)   (held over the step)
//     fmi2DoStep of the bicycle and of the controller from t_k to t_k + h
//
// The delay is exact on the communication grid: a ring buffer of (t_k, value) samples read at
// t_k - tau with linear interpolation, the initial value before t_0 + tau (as the Python rider's
// TransportDelay in cosim/cosimulation/blocks.py). A step the FMU discards (its integrator gave
// up: the configuration went where the model does not hold, e.g. the steer past 90 degrees) ends
// the ride as a fall too; the reason is kept.
//
// window.cosimRide is the state for tests: {ready, error, demo, running, finished, time,
// realTimeFactor, stepsPerSecond, steps, seconds, trajectory {t, <outputs>, T_delta, T_phi, fell,
// reason}, compare (same, or null), inputs (names), columns (CSV header), expectation
// [{check, ok, measured}], passed, unstablePole {main, compare} [1/s], player {time, playing,
// finished, frames}, frames (view frames drawn), plotDraws, live {active, bicycle, speed, tau, input,
// magnitude, pace, goal, t, T_delta, T_phi, phi, command, events [{key, down, time}] (key:
// ArrowLeft/ArrowRight or touch-left/touch-right), fell, reason, steps, frames (of the view while
// riding), verdict, liveDraws (plots drawn while riding), lane (the lane change's [x, y] or null)},
// view2d (true: no WebGL, the 2-D view), csv() (the CSV text), verdictOf({goal, speed}, {t, x, y, phi,
// fell}) (the words at the end of a ride of your own), goals {name: {label, duration [s]}}, lane
// {shift [m], from [s], to [s], tolerance [m]}}.
(function () {
  "use strict";
  const DATA = window.COSIM_DATA;
  const RIDE = DATA.ride;  // {model, linearModel, step, fallRoll, bicycles, geometry: [names]}
  const state = {
    ready: false, error: null, demo: null, running: false, finished: false, time: 0,
    realTimeFactor: null, stepsPerSecond: null, steps: 0, seconds: null, trajectory: null, compare: null,
    inputs: [], columns: [], expectation: [], passed: null, unstablePole: {}, player: null, frames: 0,
    plotDraws: 0, live: null, demosRun: {}, view2d: false,
  };
  window.cosimRide = state;
  const $ = (id) => document.getElementById(id);
  const base64Bytes = (text) => Uint8Array.from(atob(text), (ch) => ch.charCodeAt(0));
  const fail = (e) => {
    state.error = String(e && e.stack ? e.message : e);
    const box = $("ride-error");
    if (box) box.textContent = "ride: " + state.error;
    console.error(e);
  };

  // --- the WebAssembly modules, compiled once each ------------------------------------------------
  const modules = new Map();
  function moduleOf(name) {
    if (!modules.has(name)) {
      const m = DATA.modules[name];
      if (!m) throw new Error(`the page has no WebAssembly module of ${name}`);
      modules.set(name, CosimFMU.WasmFMU.fromBytes(m.description, base64Bytes(m.wasm)));
    }
    return modules.get(name);
  }

  // --- signals: sources and the exact delay -----------------------------------------------------
  function source(spec) {
    if (spec.source === "pulse")
      return (t) => (t >= spec.start - 1e-12 && t < spec.start + spec.duration - 1e-12 ? spec.amplitude : 0);
    if (spec.source === "step") return (t) => (t >= spec.start - 1e-12 ? spec.amplitude : 0);
    throw new Error(`unknown source ${spec.source}`);
  }

  // y(t) = u(t - tau) on the communication grid: samples pushed at increasing times, read with
  // linear interpolation; before the first sample's time + tau, the first sample's value.
  class Delay {
    constructor(tau, step) {
      this.tau = tau;
      this.step = step;
      this.size = Math.ceil(tau / step) + 4;  // samples within tau of now, the one before, margin
      this.t = new Float64Array(this.size);
      this.v = new Float64Array(this.size);
      this.first = 0;
      this.count = 0;
    }
    push(t, value) {
      const i = (this.first + this.count) % this.size;
      if (this.count && this.t[(i - 1 + this.size) % this.size] === t) {  // the same time: replaced
        this.v[(i - 1 + this.size) % this.size] = value;
      } else {
        if (this.count === this.size) { this.first = (this.first + 1) % this.size; this.count--; }
        this.t[(this.first + this.count) % this.size] = t;
        this.v[(this.first + this.count) % this.size] = value;
        this.count++;
      }
      const target = t - this.tau;
      const at = (k) => (this.first + k) % this.size;
      // forget what can no longer be reached (keep one sample before the horizon)
      while (this.count > 2 && this.t[at(1)] <= target) { this.first = at(1); this.count--; }
      if (target <= this.t[at(0)] + 1e-9 * this.step) return this.v[at(0)];
      let k = 1;
      while (k < this.count - 1 && this.t[at(k)] < target) k++;
      const t0 = this.t[at(k - 1)], t1 = this.t[at(k)], v0 = this.v[at(k - 1)], v1 = this.v[at(k)];
      // a delay of whole steps hits the samples: no interpolation of round-off (t - tau vs k*h)
      const near = 1e-9 * this.step;
      if (target >= t1 - near) return v1;
      if (target <= t0 + near) return v0;
      return t1 === t0 ? v1 : v0 + (v1 - v0) * (target - t0) / (t1 - t0);
    }
  }

  // --- one ride: the bicycle FMU, optionally a controller FMU, stepped on a fixed grid --------------
  class Ride {
    // spec: {values (bicycle parameters and start values), inputs {name: source}, controller?}
    // extra(t) -> {T_delta, T_phi} added before the delay of `extraDelay` (the rider in the loop)
    constructor(bike, controller, spec, step, { extra = null, extraDelay = 0 } = {}) {
      this.step = step;
      this.fmu = bike;
      this.bike = bike.instantiate({ name: "ride" });
      this.outputs = bike.names("output");
      this.inputs = bike.names("input");
      this.bike.set(spec.values);
      this.bike.setupExperiment({ tolerance: bike.defaultExperiment.tolerance, startTime: 0 });
      this.bike.enterInitializationMode();
      this.bike.exitInitializationMode();
      this.read = this.bike.reader(this.outputs);
      this.write = this.bike.writer(this.inputs);
      this.sources = this.inputs.map((name) => (spec.inputs && spec.inputs[name] ? source(spec.inputs[name]) : null));
      this.phiIndex = this.outputs.indexOf("phi");
      if (controller) {
        const c = spec.controller;
        this.ctrl = controller.instantiate({ name: "controller" });
        this.ctrl.set(c.parameters || {});
        this.ctrl.setupExperiment({ startTime: 0 });
        this.ctrl.enterInitializationMode();
        this.ctrl.exitInitializationMode();
        const names = Object.keys(c.connect);
        this.ctrlWrite = this.ctrl.writer(names);
        this.ctrlFrom = names.map((n) => this.outputs.indexOf(c.connect[n]));
        this.ctrlRead = this.ctrl.reader([c.output]);
        this.ctrlDrives = this.inputs.indexOf(c.drives);
        this.ctrlDelay = new Delay(c.delay || 0, step);
      }
      this.extra = extra;
      this.extraDelay = this.inputs.map(() => new Delay(extraDelay, step));
      this.k = 0;
      this.time = 0;
      this.u = new Float64Array(this.inputs.length);
      this.rows = [];  // [outputs..., inputs...] per communication point
      this.fell = false;
      this.done = false;
      this.reason = null;
    }

    // One communication point: record, decide the inputs, step. False once the ride ended.
    advance(stopTime) {
      if (this.done) return false;
      const t = this.k * this.step, y = this.read();
      const u = this.u;
      for (let i = 0; i < u.length; i++) u[i] = this.sources[i] ? this.sources[i](t) : 0;
      if (this.ctrl) {
        this.ctrlWrite(this.ctrlFrom.map((j) => y[j]));
        u[this.ctrlDrives] += this.ctrlDelay.push(t, this.ctrlRead()[0]);
      }
      if (this.extra) {
        const e = this.extra(t);
        for (let i = 0; i < u.length; i++) u[i] += this.extraDelay[i].push(t, e[this.inputs[i]] || 0);
      }
      const row = new Float64Array(y.length + u.length);
      row.set(y);
      row.set(u, y.length);
      this.rows.push(row);
      this.time = t;
      if (Math.abs(y[this.phiIndex]) > RIDE.fallRoll) return this.end(true, `fall: |phi| > ${RIDE.fallRoll} rad`);
      if (t >= stopTime - 1e-9 * this.step) return this.end(false, "end");
      this.write(u);
      const status = this.bike.doStep(t, this.step);
      if (this.ctrl) this.ctrl.doStep(t, this.step);
      if (status === 2) {  // the outputs are those of the last successful time
        const z = this.read(), delta = z[this.outputs.indexOf("delta")];
        this.stopped = { t: this.bike.lastSuccessfulTime, phi: z[this.phiIndex], delta };
        return this.end(true, `fall: the FMU stopped the step at t = ${this.bike.lastSuccessfulTime.toFixed(3)} s ` +
                              `(phi ${z[this.phiIndex].toFixed(2)} rad, steer ${delta.toFixed(2)} rad: the ` +
                              "configuration became singular)");
      }
      this.k++;
      return true;
    }

    end(fell, reason) {
      this.fell = fell;
      this.done = true;
      this.reason = reason;
      return false;
    }

    // The recorded ride as arrays: {t, <output>..., <input>..., fell, reason}.
    trajectory() {
      const out = { t: this.rows.map((_, k) => k * this.step), fell: this.fell, reason: this.reason,
                  stopped: this.stopped || null };
      [...this.outputs, ...this.inputs].forEach((name, j) => { out[name] = this.rows.map((r) => r[j]); });
      return out;
    }

    free() {
      for (const f of [this.read, this.write, this.ctrlWrite, this.ctrlRead]) if (f) f.free();
      this.bike.free();
      if (this.ctrl) this.ctrl.free();
    }
  }

  // Run a ride to its end as fast as the module goes; the stepping loop is timed.
  async function precompute(spec, duration) {
    const bike = await moduleOf(RIDE.model);
    const controller = spec.controller ? await moduleOf(spec.controller.model) : null;
    const ride = new Ride(bike, controller, spec, RIDE.step);
    const started = performance.now();
    while (ride.advance(duration));
    const seconds = (performance.now() - started) / 1000;
    const trajectory = ride.trajectory();
    const result = { trajectory, seconds, steps: ride.k, columns: ["time", ...ride.outputs, ...ride.inputs],
                     inputs: ride.inputs };
    ride.free();
    return result;
  }

  // --- the largest real part of the linearized bicycle's eigenvalues (p of p*tau) ------------------
  // A(v) from the WhippleLinear module's directional derivatives, as app.js does; eigenvalues by ml-matrix.
  async function unstablePole(values, speed) {
    const fmu = await moduleOf(RIDE.linearModel);
    const inst = fmu.instantiate({ name: "pole" });
    try {
      const params = {};
      for (const v of fmu.description.variables)
        if (v.causality === "parameter" && v.name in values && v.name !== "v") params[v.name] = values[v.name];
      inst.set({ ...params, v: speed });
      inst.setupExperiment({ startTime: 0 });
      inst.enterInitializationMode();
      inst.exitInitializationMode();
      const states = ["phi", "delta", "phi_dot", "delta_dot"];
      const d = inst.directional(states.map((s) => `der(${s})`), states);
      const A = d.jacobian();
      d.free();
      const e = new mlMatrix.EigenvalueDecomposition(new mlMatrix.Matrix(A));
      return Math.max(...e.realEigenvalues);
    } finally {
      inst.free();
    }
  }

  // --- expectations: the definitions of cosim/app/demos.py (check_expectation) ---------------------
  function windowAbs(t, s, t0, t1) {
    const out = [];
    for (let i = 0; i < t.length; i++)
      if ((t0 === undefined || t[i] >= t0 - 1e-12) && (t1 === undefined || t[i] <= t1 + 1e-12)) out.push(Math.abs(s[i]));
    return out;
  }
  // Least-squares slope [1/s] of log|s| over low < |s| < high before |s| first reaches high.
  function growthRate(t, s, low, high) {
    const ts = [], ls = [];
    for (let i = 0; i < t.length; i++) {
      const a = Math.abs(s[i]);
      if (a >= high) break;
      if (a > low) { ts.push(t[i]); ls.push(Math.log(a)); }
    }
    if (ts.length < 3) return NaN;
    const mt = ts.reduce((a, b) => a + b) / ts.length, ml = ls.reduce((a, b) => a + b) / ls.length;
    let num = 0, den = 0;
    for (let i = 0; i < ts.length; i++) { num += (ts[i] - mt) * (ls[i] - ml); den += (ts[i] - mt) ** 2; }
    return num / den;
  }
  function check(c, rides, duration) {
    const r = rides[c.ride], t = r.t, end = t[t.length - 1];
    const sign = (x) => (x < 0 || Object.is(x, -0) ? -1 : 1);
    switch (c.check) {
      case "falls":
        return [r.fell === c.value && (!c.value || end <= (c.before ?? duration)), `fell=${r.fell} at t=${end.toFixed(2)} s`];
      case "outlasts": {
        const o = rides.compare, oe = o.t[o.t.length - 1];
        return [o.fell && end >= c.ratio * oe, `main ends at ${end.toFixed(2)} s, compare at ${oe.toFixed(2)} s`];
      }
      case "max_abs": {
        const w = windowAbs(t, r[c.signal], c.from, c.to), m = w.length ? Math.max(...w) : NaN;
        return [w.length > 0 && (c.below === undefined || m < c.below) && (c.above === undefined || m > c.above),
                `max |${c.signal}| = ${m.toPrecision(4)}`];
      }
      case "grows": {
        const a = windowAbs(t, r[c.signal], ...c.early), b = windowAbs(t, r[c.signal], ...c.late);
        const ma = a.length ? Math.max(...a) : NaN, mb = b.length ? Math.max(...b) : NaN;
        return [a.length > 0 && b.length > 0 && mb >= c.ratio * ma, `max |${c.signal}| ${ma.toPrecision(4)} -> ${mb.toPrecision(4)}`];
      }
      case "first_excursion": {
        const first = r[c.signal].find((v) => Math.abs(v) > c.threshold);
        return [first !== undefined && sign(first) === c.sign, `first excursion ${first}`];
      }
      case "final_sign": {
        const last = r[c.signal][r[c.signal].length - 1];
        return [sign(last) === c.sign && Math.abs(last) >= (c.at_least ?? 0), `final ${c.signal} = ${last.toPrecision(4)}`];
      }
      case "growth_rate": {
        const rate = growthRate(t, r[c.signal], ...c.between);
        let ok = Number.isFinite(rate) && (c.below === undefined || rate < c.below) && (c.above === undefined || rate > c.above);
        let text = `growth rate of |${c.signal}| ${rate.toPrecision(4)} 1/s`;
        if (c.than_compare !== undefined) {
          const o = rides.compare, other = growthRate(o.t, o[c.signal], ...c.between);
          ok = ok && Number.isFinite(other) && rate <= c.than_compare * other;
          text += `, compare ${other.toPrecision(4)} 1/s`;
        }
        return [ok, text];
      }
      default:
        throw new Error(`unknown check ${c.check}`);
    }
  }

  // --- the view, the player, the plots ---------------------------------------------------------
  // playing: the trajectory in the player, playingName: the name its CSV download gets
  let view = null, player = null, plots = null, playing = null, playingName = "ride";
  const COLORS = { main: "#1f5fbf", compare: "#c0392b" };

  function geometry(values) {
    const g = {};
    for (const name of RIDE.geometry) if (name in values) g[name] = values[name];
    return g;
  }

  // The 3-D view, or without WebGL the 2-D one (a top view and a rear view) with a plain message.
  // WebGL is probed on a canvas of its own first, so that three.js is never asked for a context it
  // cannot have (it would log errors); should three.js fail anyway, the canvas is replaced by a
  // fresh one (a canvas that gave a WebGL context gives no 2-D one) and drawn in 2-D.
  let viewKey = null;  // the geometry the view draws: a view is made anew only for another one
  function ensureView(values) {
    let canvas = $("ride-canvas");
    const key = JSON.stringify(geometry(values));
    if (view && key === viewKey) return view;  // (a new WebGL renderer costs its shaders' compilation)
    if (view) view.dispose();
    view = null;
    viewKey = key;
    if (!state.view2d && CosimRide2D.webglAvailable()) {
      try {
        view = CosimRide3D.createView(canvas, geometry(values), { rider: true, follow: true });
        return view;
      } catch (e) {
        const fresh = canvas.cloneNode(false);
        canvas.replaceWith(fresh);
        canvas = fresh;
      }
    }
    if (!state.view2d) {
      state.view2d = true;
      $("ride-no-webgl").hidden = false;
      canvas.setAttribute("aria-label", "the ride in 2-D: the path from above and the bicycle's lean from behind");
    }
    view = CosimRide2D.createView(canvas, geometry(values));
    view.resize(canvas.clientWidth || 400, canvas.clientHeight || 300);
    return view;
  }

  function play(trajectory, values, name, { autoplay = true } = {}) {
    if (player) player.pause();
    ensureView(values);
    for (const id of ["ride-play", "ride-scrub", "ride-rate", "ride-csv"]) $(id).disabled = false;
    playing = trajectory;
    playingName = name;
    const scrub = $("ride-scrub"), end = trajectory.t[trajectory.t.length - 1];
    scrub.max = String(end);
    scrub.step = String(RIDE.step);
    player = CosimRide3D.createPlayer(view, trajectory, {
      rate: Number($("ride-rate").value),
      onFrame(time) {
        scrub.value = String(time);
        $("ride-time").textContent = time.toFixed(2);
        plots.setCursor(time);
        if (player) state.player = { ...player.state };  // (createPlayer may draw a first frame)
        state.frames = view.frames;
        state.plotDraws = plots.draws;
      },
      onEnd() { $("ride-play").textContent = "play"; if (player) state.player = { ...player.state }; },
    });
    state.player = { ...player.state };
    // The ride plays at once, unless the reader's system asks for reduced motion: then the first
    // frame stays until "play" is pressed.
    if (!autoplay || matchMedia("(prefers-reduced-motion: reduce)").matches) {
      $("ride-play").textContent = "play";
    } else {
      player.play();
      $("ride-play").textContent = "pause";
    }
  }

  function showTrajectories(main, compare, labels) {
    const rides = [{ ...main, label: labels.main, color: COLORS.main }];
    if (compare) rides.push({ ...compare, label: labels.compare, color: COLORS.compare, dashed: true });
    plots.setRides(rides);
  }

  // --- the demos ----------------------------------------------------------------------------------
  async function runDemo(name) {
    const demo = DATA.demos.find((d) => d.name === name);
    if (!demo) throw new Error(`no demo ${name}`);
    if (state.running) return null;  // one ride at a time (a second click waits for nothing)
    stopLive();
    Object.assign(state, { demo: name, running: true, finished: false, expectation: [], passed: null, compare: null });
    $("ride-status").textContent = `computing "${demo.title}" ...`;
    const main = await precompute(demo.ride, demo.duration);
    const compare = demo.compare ? await precompute(demo.compare, demo.duration) : null;
    // p of the linear (knife-edge) model: not for toroidal tyres, which WhippleLinear does not have
    const pole = (ride) => (ride.values.tR || ride.values.tF ? null : unstablePole(ride.values, ride.speed));
    const poles = { main: await pole(demo.ride) };
    if (demo.compare) poles.compare = await pole(demo.compare);
    const rides = { main: main.trajectory, compare: compare && compare.trajectory };
    const expectation = demo.expect.map((c) => { const [ok, measured] = check(c, rides, demo.duration); return { ...c, ok, measured }; });
    const simulated = main.trajectory.t[main.trajectory.t.length - 1];
    Object.assign(state, {
      trajectory: main.trajectory, compare: compare && compare.trajectory, inputs: main.inputs, columns: main.columns,
      seconds: main.seconds, steps: main.steps, stepsPerSecond: main.steps / main.seconds,
      realTimeFactor: simulated / main.seconds, time: simulated, expectation,
      passed: expectation.every((e) => e.ok), unstablePole: poles, running: false, finished: true,
    });
    state.demosRun[name] = { passed: state.passed, realTimeFactor: state.realTimeFactor };
    showDemoResult(demo, main, compare, poles, expectation);
    showTrajectories(main.trajectory, compare && compare.trajectory, { main: demo.ride.label, compare: demo.compare && demo.compare.label });
    $("ride-which").innerHTML = "";
    for (const [key, ride] of [["main", demo.ride], ["compare", demo.compare]]) {
      if (!ride) continue;
      const o = document.createElement("option");
      o.value = key; o.textContent = ride.label;
      $("ride-which").appendChild(o);
    }
    $("ride-which").disabled = !demo.compare;
    play(main.trajectory, demo.ride.values, name);
    return state.passed;
  }

  // --- results in the lesson's words ---------------------------------------------------------------
  // Meijaard's axes: y, roll, steer, heading and turn rate are positive to the right.
  const DEG = 180 / Math.PI;
  const side = (x) => (x > 0 ? "right" : "left");
  const ANGLES = new Set(["phi", "delta", "psi"]);
  const WORDS = { phi: "the lean", delta: "the steer angle", psi: "the heading", y: "the path", u_psi: "the turn rate",
                  x: "the distance", u_phi: "the lean rate", u_delta: "the steer rate" };
  const word = (signal) => WORDS[signal] || signal;
  // a length in words: centimetres below 10 cm, else metres
  const length = (m) => (Math.abs(m) < 0.1 ? `${Math.max(1, Math.round(Math.abs(m) * 100))} cm`
                                           : `${Math.abs(m).toFixed(2)} m`);
  const angle = (rad) => `${+(Math.abs(rad) * DEG).toPrecision(2)}\u00b0`;
  const amount = (signal, v) => (ANGLES.has(signal) ? angle(v) : signal === "y" ? length(v)
    : signal === "u_psi" ? `${angle(v)} per second` : `${+Math.abs(v).toPrecision(3)}`);
  const seconds = (t) => `${+t.toFixed(2)} s`;

  // How a ride ended, in words: it stayed up, or when and how it fell.
  function outcome(tr, duration) {
    const end = tr.t[tr.t.length - 1];
    if (!tr.fell) return tr.reason === "end" ? `stayed up for the whole ${seconds(duration)}` : `stopped at ${seconds(end)}`;
    if (tr.stopped)
      return `fell after ${seconds(end)}: it leaned ${angle(tr.stopped.phi)} to the ${side(tr.stopped.phi)} ` +
             `and steered ${angle(tr.stopped.delta)} to the ${side(tr.stopped.delta)}, as far as the model of ` +
             "the rolling bicycle goes";
    const phi = tr.phi[tr.phi.length - 1];
    return `fell to the ${side(phi)} after ${seconds(end)} (the lean passed ${angle(RIDE.fallRoll)})`;
  }

  // One expectation of a demo (cosim/app/demos.py's checks) as a sentence of what happened.
  function plainCheck(c, rides, labels) {
    const r = rides[c.ride], label = labels[c.ride], t = r.t, end = t[t.length - 1];
    switch (c.check) {
      case "falls":
        return c.value ? `${label}: the bicycle fell, after ${seconds(end)}` + (c.before ? ` (expected before ${seconds(c.before)})` : "")
                       : `${label}: the bicycle stayed up`;
      case "outlasts": {
        const o = rides.compare;
        return `${label} stayed up for ${seconds(end)}, ${labels.compare} only ${seconds(o.t[o.t.length - 1])}`;
      }
      case "max_abs": {
        const w = windowAbs(t, r[c.signal], c.from, c.to), m = w.length ? Math.max(...w) : NaN;
        const when = c.from !== undefined ? ` from ${seconds(c.from)} to ${seconds(c.to ?? end)}` : "";
        const bound = c.below !== undefined ? `stayed below ${amount(c.signal, c.below)}` : `went beyond ${amount(c.signal, c.above)}`;
        return `${label}: ${word(c.signal)} ${bound}${when} (at most ${amount(c.signal, m)})`;
      }
      case "grows": {
        const a = windowAbs(t, r[c.signal], ...c.early), b = windowAbs(t, r[c.signal], ...c.late);
        return `${label}: ${word(c.signal)} grew from ${amount(c.signal, Math.max(...a))} (${seconds(c.early[0])}\u2013` +
               `${seconds(c.early[1])}) to ${amount(c.signal, Math.max(...b))} (${seconds(c.late[0])}\u2013${seconds(c.late[1])})`;
      }
      case "first_excursion": {
        const first = r[c.signal].find((v) => Math.abs(v) > c.threshold);
        return first === undefined ? `${label}: ${word(c.signal)} hardly moved`
          : `${label}: ${word(c.signal)} first went ${amount(c.signal, first)} to the ${side(first)}`;
      }
      case "final_sign": {
        const last = r[c.signal][r[c.signal].length - 1];
        return `${label}: at the end ${word(c.signal)} was ${amount(c.signal, last)} to the ${side(last)}`;
      }
      case "growth_rate": {
        const rate = growthRate(t, r[c.signal], ...c.between);
        let text = `${label}: ${word(c.signal)} doubled every ${seconds(Math.LN2 / rate)}`;
        if (c.than_compare !== undefined) {
          const o = rides.compare, other = growthRate(o.t, o[c.signal], ...c.between);
          text += `, with ${labels.compare} every ${seconds(Math.LN2 / other)}`;
        }
        return text;
      }
      default:
        return `${label}: ${c.check}`;
    }
  }

  // The story of a path that first goes one way and ends up the other: counter-steering.
  function counterSteering(demo, rides, labels) {
    for (const key of ["main", "compare"]) {
      const checks = demo.expect.filter((c) => c.ride === key && c.signal === "y");
      const first = checks.find((c) => c.check === "first_excursion"), last = checks.find((c) => c.check === "final_sign");
      if (!first || !last || !rides[key]) continue;
      const y = rides[key].y, a = y.find((v) => Math.abs(v) > first.threshold), b = y[y.length - 1];
      if (a !== undefined && Math.sign(a) !== Math.sign(b))
        return `${labels[key]}: the path first went ${length(a)} ${side(a)}, then ${length(b)} ${side(b)}: counter-steering.`;
    }
    return null;
  }

  function showDemoResult(demo, main, compare, poles, expectation) {
    const fmt = (x, d = 1) => x.toLocaleString("en", { maximumFractionDigits: d });
    const tau = (ride) => (ride.controller && ride.controller.delay ? ride.controller.delay : 0);
    const labels = { main: demo.ride.label, compare: demo.compare && demo.compare.label };
    const rides = { main: main.trajectory, compare: compare && compare.trajectory };
    // what a student reads: how each ride ended and what that shows
    const lines = [];
    const story = counterSteering(demo, rides, labels);
    if (story) lines.push(story);
    for (const key of ["main", "compare"]) {
      if (!rides[key]) continue;
      let text = `${labels[key]}: ${outcome(rides[key], demo.duration)}.`;
      const p = poles[key];
      if (p !== null && p !== undefined)
        // p: the largest real part of the linearized bicycle's eigenvalues, hands off the handlebar
        text += p > 0 ? ` With nobody steering, a small lean grows at this speed: it doubles every ${seconds(Math.LN2 / p)}.`
                      : " With nobody steering, the bicycle recovers from a small lean at this speed.";
      lines.push(text);
    }
    $("ride-status").textContent = lines.join("\n");
    const list = $("ride-expectation");
    list.innerHTML = "";
    for (const e of expectation) {
      const li = document.createElement("li");
      li.className = e.ok ? "ok" : "bad";
      li.textContent = `${e.ok ? "\u2713" : "\u2717 not as expected:"} ${plainCheck(e, rides, labels)}`;
      list.appendChild(li);
    }
    // the engineer's numbers, folded away
    const technical = [`${main.steps} steps of ${RIDE.step} s in ${fmt(main.seconds * 1e3)} ms: ${fmt(main.steps / main.seconds, 0)} ` +
                       `steps/s, ${fmt(main.trajectory.t[main.trajectory.t.length - 1] / main.seconds, 0)}\u00d7 real time.`];
    for (const key of ["main", "compare"]) {
      if (!rides[key]) continue;
      const ride = key === "main" ? demo.ride : demo.compare, p = poles[key];
      let text = `${labels[key]}: ${rides[key].reason} (t = ${rides[key].t[rides[key].t.length - 1].toFixed(2)} s)`;
      if (p !== null && p !== undefined) {
        text += `; largest Re \u03bb of the uncontrolled linearized bicycle p = ${p.toFixed(3)} 1/s`;
        if (tau(ride)) text += `, \u03c4 = ${tau(ride)} s, p\u03c4 = ${(p * tau(ride)).toFixed(3)}`;
      }
      technical.push(text + ".");
    }
    for (const e of expectation)
      technical.push(`${e.ok ? "\u2713" : "\u2717"} ${e.check} (${e.ride}${e.signal ? ", " + e.signal : ""}): ${e.measured}`);
    $("ride-technical-text").textContent = technical.join("\n");
    $("ride-technical").hidden = false;
  }

  function selectDemo(name) {
    const demo = DATA.demos.find((d) => d.name === name);
    $("demo-title").textContent = demo.title;
    $("demo-references").textContent = demo.references.join(", ");
    const text = $("demo-text");
    text.innerHTML = "";
    for (const para of demo.text.split(/\n\s*\n/)) {
      const p = document.createElement("p");
      p.textContent = para.trim();
      text.appendChild(p);
    }
    for (const li of document.querySelectorAll("#demo-list li")) li.classList.toggle("chosen", li.dataset.demo === name);
  }

  // --- CSV of the played ride -----------------------------------------------------------------------
  function csv(trajectory = state.trajectory) {
    if (!trajectory) return "";
    const names = state.columns.slice(1);
    const lines = [state.columns.join(",")];
    for (let k = 0; k < trajectory.t.length; k++) lines.push([trajectory.t[k], ...names.map((n) => trajectory[n][k])].join(","));
    return lines.join("\n") + "\n";
  }
  state.csv = () => csv(playing || state.trajectory);

  function download() {
    stopLive();  // a ride of your own: what was ridden so far
    const text = state.csv();
    if (!text) return;
    const a = document.createElement("a");
    a.href = URL.createObjectURL(new Blob([text], { type: "text/csv" }));
    a.download = `${playingName}.csv`;
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 1000);
  }

  // --- rider in the loop: real time or slow motion, keyboard / gamepad / touch, delay, a goal ------
  const keys = { ArrowLeft: false, ArrowRight: false };
  const touch = { left: false, right: false };  // the on-screen buttons, held
  let liveRide = null, liveFrame = null, liveValues = null;

  // The goals: stay up for 20 s; follow a lane that moves 1 m to the right (y > 0, Meijaard's
  // axes), as the paper's lane change, between 4 s and 7 s of riding at the chosen speed.
  const LANE = { shift: 1.0, from: 4.0, to: 7.0, tolerance: 0.5 };  // [m, s, s, m]
  const GOALS = {
    free: { label: "no goal: ride as long as you like", duration: 600 },
    "stay-up": { label: "stay up for 20 s", duration: 20 },
    "lane-change": { label: "follow a lane change (1 m to the right)", duration: 10 },
  };
  // The lane's centre y [m] at the distance d [m] ridden, at the speed v [m/s] (cosine blend).
  function laneAt(d, v) {
    const a = LANE.from * Math.abs(v), b = LANE.to * Math.abs(v);
    if (d <= a) return 0;
    if (d >= b) return LANE.shift;
    return LANE.shift * (1 - Math.cos(Math.PI * (d - a) / (b - a))) / 2;
  }
  // the lane's centre line as points [x, y] over the goal's ride (riding backwards: x < 0)
  function lanePath(v) {
    const out = [], length = GOALS["lane-change"].duration * Math.abs(v), dir = v < 0 ? -1 : 1;
    for (let k = 0; k <= 200; k++) { const d = length * k / 200; out.push([dir * d, laneAt(d, v)]); }
    return out;
  }

  state.verdictOf = (live, tr) => verdict(live, tr);
  state.goals = GOALS;
  state.lane = LANE;

  function command() {
    let c = (keys.ArrowRight || touch.right ? 1 : 0) - (keys.ArrowLeft || touch.left ? 1 : 0);
    const pads = navigator.getGamepads ? Array.from(navigator.getGamepads()).filter(Boolean) : [];
    if (pads.length && pads[0].axes.length && Math.abs(pads[0].axes[0]) > 0.05) c += pads[0].axes[0];
    return c * Number($("live-magnitude").value);
  }

  // The verdict of a finished ride of your own, in plain words.
  function verdict(live, tr) {
    const end = tr.t[tr.t.length - 1], goal = GOALS[live.goal];
    const how = tr.fell ? `the bicycle fell after ${seconds(end)}` : `you stopped at ${seconds(end)}`;
    const phiMax = tr.phi.reduce((m, v) => (Math.abs(v) > Math.abs(m) ? v : m), 0);
    const lean = `the largest lean was ${angle(phiMax)}${Math.abs(phiMax) > 0 ? " to the " + side(phiMax) : ""}`;
    const hint = tr.fell ? " Try a shorter delay \u03c4, slow motion, or catch the lean earlier: steer into it." : "";
    if (live.goal === "stay-up") {
      if (!tr.fell && end >= goal.duration - 1e-9)
        return `Goal reached: you kept the bicycle up for ${seconds(goal.duration)}; ${lean}.`;
      return `Goal not reached: ${how}, before ${seconds(goal.duration)}; ${lean}.${hint}`;
    }
    if (live.goal === "lane-change") {
      const d = tr.x.map((x) => Math.abs(x)), miss = tr.y.map((y, i) => y - laneAt(d[i], live.speed));
      let worst = 0;
      for (let i = 1; i < miss.length; i++) if (Math.abs(miss[i]) > Math.abs(miss[worst])) worst = i;
      const stayed = `your path was at most ${length(miss[worst])} from the lane's centre ` +
                     `(${length(miss[worst])} ${side(miss[worst])} of it at ${seconds(tr.t[worst])})`;
      // counter-steering: to go right, the path first goes a little left (from where the lane starts to move)
      const from = tr.t.findIndex((t) => t >= LANE.from), y0 = from < 0 ? 0 : tr.y[from];
      const first = from < 0 ? undefined : tr.y.slice(from).find((y) => Math.abs(y - y0) > 0.01);
      const last = tr.y[tr.y.length - 1];
      const story = first !== undefined && first < y0 && last > y0
        ? ` The path first went ${length(first - y0)} left, then ${length(last - y0)} right: counter-steering.` : "";
      if (tr.fell || end < goal.duration - 1e-9)
        return `Goal not reached: ${how}, before the end of the lane change (${seconds(goal.duration)}); ${stayed}.${hint}`;
      const ok = Math.abs(miss[worst]) <= LANE.tolerance;
      return (ok ? `Goal reached: you followed the lane; ${stayed}.`
                 : `Goal not reached: ${stayed}, more than ${length(LANE.tolerance)} (half a lane).`) + story;
    }
    return `${how[0].toUpperCase()}${how.slice(1)}; ${lean}.`;
  }

  // The ride so far on the plots (and its lane), as the ride goes.
  function drawLive(final) {
    if (!liveRide) return;
    const tr = liveRide.trajectory();
    showTrajectories(tr, null, { main: final ? `ridden by you (\u03c4 = ${state.live.tau} s)` : "your ride so far" });
    state.live.liveDraws = (state.live.liveDraws || 0) + 1;
    return tr;
  }

  // The demo's texts, ticks and player are not about this ride: cleared while it runs.
  function clearDemoResult() {
    if (player) player.pause();
    player = null;
    state.demo = null;
    state.player = null;
    $("ride-status").textContent = "";
    $("ride-expectation").innerHTML = "";
    $("ride-technical").hidden = true;
    $("ride-which").innerHTML = "";
    $("ride-which").disabled = true;
    for (const id of ["ride-play", "ride-scrub", "ride-rate", "ride-csv"]) $(id).disabled = true;
    $("ride-scrub").value = "0";
    $("ride-time").textContent = "0.00";
  }

  function liveStatus(live, q) {
    const lean = Math.abs(q.phi) < 0.5 / DEG ? "upright" : `leaning ${angle(q.phi)} to the ${side(q.phi)}`;
    const steer = Math.abs(q.delta) < 0.5 / DEG ? "steering straight" : `steering ${angle(q.delta)} to the ${side(q.delta)}`;
    const c = live.command.length ? live.command[live.command.length - 1] : 0;
    const yours = c === 0 ? "no torque from you" : `your ${live.input === "T_phi" ? "lean" : "steer"} torque: ${side(c)}`;
    let gust = "";
    if (live.gust) {
      const g = RIDE.gust, t = liveRide.time;
      gust = t < g.start ? ` \u00b7 the gust comes in ${(g.start - t).toFixed(1)} s` : t < g.start + g.duration ? " \u00b7 the gust!" : "";
    }
    return `t = ${liveRide.time.toFixed(1)} s \u00b7 ${lean} \u00b7 ${steer} \u00b7 ${yours}${gust}`;
  }

  async function startLive() {
    stopLive();
    clearDemoResult();
    keys.ArrowLeft = keys.ArrowRight = touch.left = touch.right = false;
    const choice = RIDE.bicycles.find((b) => b.name === $("live-bicycle").value);
    const speed = Number($("live-speed").value) * (choice.backwards ? -1 : 1);
    const values = { ...choice.values, u_R0: -speed / choice.values.rR };
    const tau = Number($("live-delay").value), mode = $("live-mode").value;
    const input = mode === "lean" ? "T_phi" : "T_delta";
    const goal = $("live-goal").value, pace = Number($("live-pace").value);
    const bike = await moduleOf(RIDE.model);
    const live = { active: true, bicycle: choice.name, speed, tau, input, magnitude: Number($("live-magnitude").value),
                   pace, goal, t: [], T_delta: [], T_phi: [], phi: [], command: [], events: [], fell: false, reason: null,
                   steps: 0, verdict: null, liveDraws: 0 };
    state.live = live;
    $("live-verdict").textContent = "";
    // the gust: without a disturbance the upright bicycle, even the rear-steered one, stays up
    // exactly (an equilibrium) and the student feels nothing
    const inputs = $("live-push").checked ? { T_phi: { source: "pulse", ...RIDE.gust } } : {};
    live.gust = $("live-push").checked;
    try {
      liveRide = new Ride(bike, null, { values, inputs }, RIDE.step, {
        extra: (t) => { const c = command(); live.command.push(c); return { [input]: c }; }, extraDelay: tau });
      liveValues = values;
      ensureView(values);
      if (view.setTarget) view.setTarget(goal === "lane-change" ? lanePath(speed) : null);
    } catch (e) {
      live.active = false;  // nothing runs: the ride is not left "active"
      live.reason = "could not start";
      throw e;
    }
    live.lane = goal === "lane-change" ? lanePath(speed) : null;
    plots.setTarget(goal === "lane-change"
      ? (() => { const pts = lanePath(speed); return { label: "the lane to follow", x: pts.map((q) => q[0]), y: pts.map((q) => q[1]) }; })()
      : null);
    playing = null;
    let last = performance.now(), accumulator = 0;
    const stop = GOALS[goal].duration;  // [s] of riding at most
    const frame = (now) => {
      if (!live.active) return;
      accumulator += Math.min(0.1, (now - last) / 1000) * pace;  // at most 0.1 s per frame (a hidden tab)
      last = now;
      while (accumulator >= RIDE.step && live.active) {
        accumulator -= RIDE.step;
        const going = liveRide.advance(stop);
        const row = liveRide.rows[liveRide.rows.length - 1], n = liveRide.outputs.length;
        live.t.push(liveRide.time);
        live.T_delta.push(row[n + liveRide.inputs.indexOf("T_delta")]);
        live.T_phi.push(row[n + liveRide.inputs.indexOf("T_phi")]);
        live.phi.push(row[liveRide.phiIndex]);
        live.steps++;
        if (!going) { live.active = false; live.fell = liveRide.fell; live.reason = liveRide.reason; }
      }
      const tr = liveRide.rows[liveRide.rows.length - 1];
      if (tr) {
        const o = liveRide.outputs, q = {};
        for (const name of ["x", "y", "psi", "phi", "theta", "delta", "thetaR", "thetaF"]) q[name] = tr[o.indexOf(name)];
        view.setPose(q);
        if (live.steps % 10 === 0 || !live.active) {
          const xi = o.indexOf("x"), yi = o.indexOf("y");
          view.setPath(liveRide.rows.map((r) => [r[xi], r[yi]]));
        }
        view.render();
        state.frames = live.frames = view.frames;
        if (live.steps - (live.plottedAt || 0) >= 10 && live.active) { live.plottedAt = live.steps; drawLive(false); }
        $("live-status").textContent = liveStatus(live, q);
      }
      if (live.active) liveFrame = requestAnimationFrame(frame);
      else finishLive();
    };
    liveFrame = requestAnimationFrame(frame);
    $("live-start").textContent = "restart";
    document.body.classList.add("riding");
    // on a phone the 3-D view is a screen above the settings: show it, the buttons stay at the bottom
    if (window.matchMedia("(max-width: 700px), (pointer: coarse)").matches) $("ride-view").scrollIntoView({ block: "start" });
  }

  function finishLive() {
    document.body.classList.remove("riding");
    if (!liveRide) return;
    const tr = drawLive(true);
    Object.assign(state, { trajectory: tr, compare: null, columns: ["time", ...liveRide.outputs, ...liveRide.inputs],
                           inputs: liveRide.inputs });
    liveRide.free();
    liveRide = null;
    const live = state.live;
    live.verdict = verdict(live, tr);
    $("live-verdict").textContent = live.verdict;
    $("live-status").textContent = `t = ${tr.t[tr.t.length - 1].toFixed(1)} s: ` +
      (live.reason === "stopped" ? "stopped" : live.reason === "end" ? "the end of the goal's ride" : "the bicycle fell");
    for (const id of ["ride-play", "ride-scrub", "ride-rate", "ride-csv"]) $(id).disabled = false;
    // your ride in the player, paused at its end: scrub it back, play it, download it
    play(tr, liveValues, `ride-yourself-${live.bicycle}`, { autoplay: false });
    if (view.setTarget) view.setTarget(live.goal === "lane-change" ? lanePath(live.speed) : null);
    player.seek(tr.t[tr.t.length - 1]);
    state.player = { ...player.state };
  }

  function stopLive() {
    if (state.live && state.live.active) {
      state.live.active = false;
      state.live.reason = "stopped";
      if (liveFrame) cancelAnimationFrame(liveFrame);
      finishLive();
    }
  }

  function onKey(event, down) {
    if (event.key === "Escape" && down && state.live && state.live.active) {
      event.preventDefault();
      stopLive();
      return;
    }
    if (!(event.key in keys) || !state.live || !state.live.active) return;
    event.preventDefault();
    if (keys[event.key] === down) return;  // auto-repeat
    keys[event.key] = down;
    state.live.events.push({ key: event.key, down, time: liveRide ? liveRide.k * RIDE.step : null });
  }

  // An on-screen button held (pointer down .. up, cancel or leaving it): a torque to its side.
  function touchButton(button, which) {
    const set = (down, event) => {
      if (event) event.preventDefault();
      if (touch[which] === down) return;
      touch[which] = down;
      button.classList.toggle("held", down);
      if (state.live && state.live.active)
        state.live.events.push({ key: `touch-${which}`, down, time: liveRide ? liveRide.k * RIDE.step : null });
    };
    button.addEventListener("pointerdown", (e) => {
      set(true, e);
      if (button.setPointerCapture && e.pointerId !== undefined) { try { button.setPointerCapture(e.pointerId); } catch (_) { /* a synthetic pointer */ } }
    });
    for (const type of ["pointerup", "pointercancel", "lostpointercapture"]) button.addEventListener(type, (e) => set(false, e));
    button.addEventListener("contextmenu", (e) => e.preventDefault());  // a long press is a torque, not a menu
    // the keyboard on a focused button: held while Space or Enter is down
    button.addEventListener("keydown", (e) => { if ((e.key === " " || e.key === "Enter") && !e.repeat) set(true, e); });
    button.addEventListener("keyup", (e) => { if (e.key === " " || e.key === "Enter") set(false, e); });
  }

  // The texts that follow the choices: the buttons' side words, the gust, the rear-steered defaults.
  function liveTexts() {
    const lean = $("live-mode").value === "lean";
    $("live-left").textContent = `\u25c0 ${lean ? "lean" : "steer"} left`;
    $("live-right").textContent = `${lean ? "lean" : "steer"} right \u25b6`;
    const g = RIDE.gust;
    $("live-push-text").textContent = `a gust pushes the bicycle to the right at t = ${g.start} s of the ride ` +
      `(a roll torque of ${g.amplitude} N\u00b7m for ${g.duration} s, like a shove of about ${g.amplitude} N at the ` +
      "rider's shoulders); the status below counts down to it";
  }

  // The rear-steered bicycle falls within a fraction of a second at walking speed: it starts
  // slower and in slow motion, so that a person can try (and fail); the others in real time.
  const REAR_STEERED = { speed: 2, pace: 0.25 };
  function liveBicycleChosen() {
    const choice = RIDE.bicycles.find((b) => b.name === $("live-bicycle").value);
    const setRange = (id, v) => { $(id).value = String(v); $(id).dispatchEvent(new Event("input")); };
    if (choice.backwards) { setRange("live-speed", REAR_STEERED.speed); $("live-pace").value = String(REAR_STEERED.pace); }
    else $("live-pace").value = "1";
  }

  // --- the page -------------------------------------------------------------------------------------
  // The 3-D view at its canvas's CSS size (index.html's style makes it fit the window; the view
  // scales by the pixel ratio itself); before a ride, the empty canvas is sized the same way.
  function fitView() {
    const canvas = $("ride-canvas"), dpr = Math.min(window.devicePixelRatio || 1, 2);
    const w = canvas.clientWidth, h = canvas.clientHeight;
    if (!w || !h) return;
    if (view) { view.resize(w, h); view.render(); return; }
    canvas.width = Math.floor(w * dpr);
    canvas.height = Math.floor(h * dpr);
  }

  function build() {
    plots = CosimPlots.create($("ride-plots"));
    fitView();
    // a new window size or pixel ratio: the plots and the 3-D view drawn again at their new size
    window.addEventListener("resize", () => { plots.redraw(); fitView(); });
    const list = $("demo-list");
    for (const d of DATA.demos) {
      const li = document.createElement("li");
      li.dataset.demo = d.name;
      const b = document.createElement("button");
      b.id = `demo-run-${d.name}`;
      b.textContent = "run";
      b.setAttribute("aria-label", `run: ${d.title}`);  // six buttons "run": a screen reader tells them apart
      b.addEventListener("click", () => { selectDemo(d.name); runDemo(d.name).catch(fail); });
      const title = document.createElement("a");
      title.href = "#ride";
      title.textContent = d.title;
      title.addEventListener("click", (e) => { e.preventDefault(); selectDemo(d.name); });
      li.append(b, " ", title);
      list.appendChild(li);
    }
    $("ride-play").addEventListener("click", () => {
      if (!player) return;
      if (player.state.playing) { player.pause(); $("ride-play").textContent = "play"; }
      else { if (player.state.finished) player.seek(0); player.play(); $("ride-play").textContent = "pause"; }
      state.player = { ...player.state };
    });
    $("ride-scrub").addEventListener("input", () => {
      if (!player) return;
      player.seek(Number($("ride-scrub").value));
      plots.setCursor(Number($("ride-scrub").value));
      state.player = { ...player.state };
      state.frames = view.frames;
    });
    $("ride-rate").addEventListener("change", () => { if (player) player.setRate(Number($("ride-rate").value)); });
    $("ride-which").addEventListener("change", () => {
      const demo = DATA.demos.find((d) => d.name === state.demo);
      if (!demo) return;
      const key = $("ride-which").value;
      play(key === "compare" ? state.compare : state.trajectory, (key === "compare" ? demo.compare : demo.ride).values,
           key === "compare" ? `${demo.name}-compare` : demo.name);
    });
    $("ride-csv").addEventListener("click", download);
    for (const b of RIDE.bicycles) {
      const o = document.createElement("option");
      o.value = b.name; o.textContent = b.label;
      $("live-bicycle").appendChild(o);
    }
    const show = (id, unit) => { $(`${id}-value`).textContent = `${$(id).value} ${unit}`; };
    for (const [id, unit] of [["live-speed", "m/s"], ["live-delay", "s"], ["live-magnitude", "N\u00b7m"]]) {
      $(id).addEventListener("input", () => show(id, unit));
      show(id, unit);
    }
    for (const [key, goal] of Object.entries(GOALS)) $("live-goal").add(new Option(goal.label, key));
    touchButton($("live-left"), "left");
    touchButton($("live-right"), "right");
    $("live-mode").addEventListener("change", liveTexts);
    $("live-bicycle").addEventListener("change", liveBicycleChosen);
    liveTexts();
    $("live-start").addEventListener("click", () => startLive().catch(fail));
    $("live-stop").addEventListener("click", stopLive);
    window.addEventListener("keydown", (e) => onKey(e, true));
    window.addEventListener("keyup", (e) => onKey(e, false));
    state.run = (name) => { selectDemo(name); return runDemo(name); };
  }

  async function start() {
    build();
    await moduleOf(RIDE.model);
    selectDemo(DATA.demos[0].name);
    state.ready = true;
  }

  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", () => start().catch(fail));
  else start().catch(fail);
})();
