// fmu.js -- run a bicycle FMU compiled to WebAssembly by `cosim build --wasm` (cosim/wasm/build.py)
// in the browser: an ES module without dependencies.
//
//   import { WasmFMU } from "./fmu.js";
//   const fmu = await WasmFMU.load("wasm/Bicycle_Bicycles_Whipple.json");   // + the .wasm beside it
//   const bike = fmu.instantiate();                  // an FMI 2.0 Co-Simulation instance
//   bike.set({ u_phi0: 0.5 });                       // parameters and start values, by name
//   bike.setupExperiment({ tolerance: 1e-10, startTime: 0 });
//   bike.enterInitializationMode(); bike.exitInitializationMode();
//   for (let k = 0; k < 1000; k++) bike.doStep(k * 0.01, 0.01);   // or bike.simulate({...})
//   bike.get("phi");
//   const d = bike.directional(["der(phi)"], ["phi"]); d.jacobian(); d.free();   // A of a linear model
//
// The module is the FMU's own C code (generated model + FMI runtime) with the small API of
// wasm_api.c; NAME.json (written from the FMU's modelDescription.xml) gives the value references.
// The module imports nothing; should a future one import WASI functions, minimal stand-ins are
// given (no file system, clock from performance.now, random from crypto.getRandomValues).

export const JSON_FORMAT = 1;

const STATUS = ["OK", "Warning", "Discard", "Error", "Fatal"];
const FMI2_LAST_SUCCESSFUL_TIME = 2;
const FMI2_TERMINATED = 3;

// An FMI call returned fmi2Error or fmi2Fatal (or an argument was refused): the message has the
// FMU's log lines of the call.
export class FMIError extends Error {
  constructor(message, status, log) {
    super(message);
    this.name = "FMIError";
    this.status = status;  // 0 OK .. 4 Fatal (or undefined: refused before any FMI call)
    this.log = log || [];  // [{status, category, instance, message}]
  }
}

// WASI preview 1 stand-ins for whatever the module imports (nothing today): stdout and stderr
// are collected into `output`, other files do not exist, exit throws.
function wasiImports(module, state) {
  const ERRNO_BADF = 8, ERRNO_NOSYS = 52;
  const view = () => new DataView(state.memory.buffer);
  const known = {
    fd_write(fd, iovs, count, written) {
      if (fd !== 1 && fd !== 2) return ERRNO_BADF;
      const v = view();
      let n = 0;
      for (let i = 0; i < count; i++) {
        const ptr = v.getUint32(iovs + 8 * i, true), len = v.getUint32(iovs + 8 * i + 4, true);
        state.output += new TextDecoder().decode(new Uint8Array(state.memory.buffer, ptr, len));
        n += len;
      }
      v.setUint32(written, n, true);
      return 0;
    },
    proc_exit(code) { throw new FMIError(`the WebAssembly module exited with code ${code}`); },
    clock_time_get(id, precision, out) {
      view().setBigUint64(out, BigInt(Math.round(performance.now() * 1e6)), true);
      return 0;
    },
    random_get(ptr, len) { crypto.getRandomValues(new Uint8Array(state.memory.buffer, ptr, len)); return 0; },
    environ_sizes_get(count, size) { const v = view(); v.setUint32(count, 0, true); v.setUint32(size, 0, true); return 0; },
    environ_get() { return 0; },
    args_sizes_get(count, size) { const v = view(); v.setUint32(count, 0, true); v.setUint32(size, 0, true); return 0; },
    args_get() { return 0; },
  };
  const imports = {};
  for (const { module: from, name, kind } of WebAssembly.Module.imports(module)) {
    if (from !== "wasi_snapshot_preview1" || kind !== "function")
      throw new FMIError(`the WebAssembly module imports ${from}.${name} (${kind}), which fmu.js does not provide`);
    imports[from] = imports[from] || {};
    imports[from][name] = known[name] || (() => ERRNO_NOSYS);
  }
  return imports;
}

// A compiled model: its description (NAME.json) and the instantiated WebAssembly module. Several
// instances of one model may exist at a time (they share the module's memory and log buffer).
export class WasmFMU {
  // Fetch NAME.json from `url` and the module it names from the same folder.
  static async load(url) {
    const base = new URL(url, globalThis.location ? globalThis.location.href : undefined);
    const response = await fetch(base);
    if (!response.ok) throw new FMIError(`cannot load ${base}: HTTP ${response.status}`);
    const description = await response.json();
    const wasmUrl = new URL(description.wasm.file, base);
    const wasm = await fetch(wasmUrl);
    if (!wasm.ok) throw new FMIError(`cannot load ${wasmUrl}: HTTP ${wasm.status}`);
    return WasmFMU.fromBytes(description, await wasm.arrayBuffer());
  }

  // From the parsed NAME.json and the bytes of NAME.wasm (e.g. embedded in a page opened from file://).
  static async fromBytes(description, bytes) {
    if (description.format !== JSON_FORMAT)
      throw new FMIError(`model description format ${description.format}, fmu.js reads ${JSON_FORMAT}`);
    const module = await WebAssembly.compile(bytes);
    const state = { memory: null, output: "" };
    const instance = await WebAssembly.instantiate(module, wasiImports(module, state));
    state.memory = instance.exports.memory;
    instance.exports._initialize();  // a reactor: the C library's constructors, once
    return new WasmFMU(description, instance.exports, state);
  }

  constructor(description, exports, state) {
    this.description = description;
    this.exports = exports;
    this.state = state;
    this.variables = new Map(description.variables.map((v) => [v.name, v]));
  }

  get modelName() { return this.description.modelName; }
  get defaultExperiment() { return this.description.defaultExperiment || {}; }

  // The variable `name` (its entry of NAME.json); FMIError if the model has none.
  variable(name) {
    const v = this.variables.get(name);
    if (!v) throw new FMIError(`${this.modelName} has no variable '${name}'`);
    return v;
  }

  // Names of the variables of a causality ("output", "input", "parameter", "local", ...).
  names(causality) {
    return this.description.variables.filter((v) => v.causality === causality).map((v) => v.name);
  }

  // A new Co-Simulation instance (FMIError with the FMU's messages if it is refused).
  instantiate({ name = "instance", loggingOn = false } = {}) {
    const e = this.exports;
    const text = this.string(name), guid = this.string(this.description.guid);
    let c;
    try {
      c = e.wasm_instantiate(text, guid, loggingOn ? 1 : 0);
    } finally {
      e.wasm_free(text);
      e.wasm_free(guid);
    }
    if (!c) throw new FMIError(`fmi2Instantiate of ${this.modelName} failed`, 3, this.readLog());
    return new Instance(this, c);
  }

  // A NUL-terminated UTF-8 copy of `text` in the module's memory (free it with exports.wasm_free).
  string(text) {
    const bytes = new TextEncoder().encode(text);
    const ptr = this.exports.wasm_alloc(bytes.length + 1);
    new Uint8Array(this.state.memory.buffer, ptr, bytes.length + 1).set([...bytes, 0]);
    return ptr;
  }

  // The log lines written since the last call (and empties the buffer).
  readLog() {
    const e = this.exports;
    const text = new TextDecoder().decode(new Uint8Array(this.state.memory.buffer, e.wasm_log_pointer(),
                                                         e.wasm_log_length()));
    const dropped = e.wasm_log_dropped();
    e.wasm_log_clear();
    const lines = text.split("\n").filter((line) => line).map((line) => {
      const [status, category, instance, ...message] = line.split("\t");
      return { status: Number(status), category, instance, message: message.join("\t") };
    });
    if (dropped) lines.push({ status: 1, category: "logStatusWarning", instance: "",
                              message: `${dropped} messages did not fit into the log buffer` });
    return lines;
  }
}

// One FMI 2.0 Co-Simulation instance. Variables are named (or given by value reference).
export class Instance {
  constructor(fmu, component) {
    this.fmu = fmu;
    this.c = component;
    this.log = [];  // every log line of this model's instances, [{status, category, instance, message}]
    this.time = 0;  // [s] the communication point reached (setupExperiment's startTime, then t + h of each step)
  }

  // The C instance (FMIError once it was freed: a freed pointer must not reach the runtime).
  get h() {
    if (!this.c) throw new FMIError(`the instance of ${this.fmu.modelName} was freed`);
    return this.c;
  }

  // Collects the log and throws FMIError if an FMI call returned Error or Fatal.
  check(status, what) {
    const lines = this.fmu.readLog();
    this.log.push(...lines);
    if (status >= 3) {
      const said = lines.filter((l) => l.status >= 2).map((l) => l.message);
      throw new FMIError(`${what}: fmi2${STATUS[status]}${said.length ? ": " + said[said.length - 1] : ""}`,
                         status, this.log.slice());
    }
    return status;
  }

  variableOf(nameOrVr) {
    if (typeof nameOrVr === "number") {
      const v = this.fmu.description.variables.find((x) => x.valueReference === nameOrVr && x.type === "Real");
      return v || { name: `#${nameOrVr}`, valueReference: nameOrVr, type: "Real" };
    }
    return this.fmu.variable(nameOrVr);
  }

  // set("phi0", 0.1), set(14, 1.0) or set({phi0: 0.1, v: 4}): by name or value reference, by type.
  set(nameOrValues, value) {
    if (typeof nameOrValues === "object") {
      for (const [name, v] of Object.entries(nameOrValues)) this.set(name, v);
      return;
    }
    const v = this.variableOf(nameOrValues), e = this.fmu.exports;
    const vr = v.valueReference;
    let status;
    if (v.type === "Real") status = e.wasm_set_real(this.h, vr, Number(value));
    else if (v.type === "Integer" || v.type === "Enumeration") {
      if (!Number.isInteger(value)) throw new FMIError(`${v.name} is an Integer variable, got ${value}`);
      status = e.wasm_set_integer(this.h, vr, value);
    } else if (v.type === "Boolean") status = e.wasm_set_boolean(this.h, vr, value ? 1 : 0);
    else throw new FMIError(`${v.name}: cannot set a ${v.type} variable`);
    this.check(status, `set ${v.name}`);
  }

  // get("phi") -> number; get(["phi", "delta"]) -> [numbers] (Booleans as true/false).
  get(names) {
    if (Array.isArray(names)) return names.map((n) => this.get(n));
    const v = this.variableOf(names), e = this.fmu.exports;
    let value;
    if (v.type === "Real") value = e.wasm_get_real(this.h, v.valueReference);
    else if (v.type === "Integer" || v.type === "Enumeration") value = e.wasm_get_integer(this.h, v.valueReference);
    else if (v.type === "Boolean") value = e.wasm_get_boolean(this.h, v.valueReference) !== 0;
    else throw new FMIError(`${v.name}: cannot get a ${v.type} variable`);
    this.check(e.wasm_last_status(), `get ${v.name}`);
    return value;
  }

  // A reader of many Real values at once (one FMI call per read): read() -> Float64Array;
  // read.free() releases its arrays in the module's memory.
  reader(names) {
    const e = this.fmu.exports, n = names.length;
    const vrs = names.map((name) => this.variableOf(name));
    for (const v of vrs) if (v.type !== "Real") throw new FMIError(`${v.name} is not a Real variable`);
    const vrPtr = e.wasm_alloc(4 * n), valuesPtr = e.wasm_alloc(8 * n);
    new Uint32Array(this.fmu.state.memory.buffer, vrPtr, n).set(vrs.map((v) => v.valueReference));
    const read = () => {
      this.check(e.wasm_get_reals(this.h, vrPtr, n, valuesPtr), "get");
      // a new view each time: the memory's buffer is replaced when the C heap grows
      return new Float64Array(this.fmu.state.memory.buffer, valuesPtr, n).slice();
    };
    read.free = () => { e.wasm_free(vrPtr); e.wasm_free(valuesPtr); };
    return read;
  }

  // A writer of many Real values at once (one FMI call per write): write(values) sets `names`
  // to `values` (in that order); write.free() releases its arrays in the module's memory.
  writer(names) {
    const e = this.fmu.exports, n = names.length;
    const vrs = names.map((name) => this.variableOf(name));
    for (const v of vrs) if (v.type !== "Real") throw new FMIError(`${v.name} is not a Real variable`);
    const vrPtr = e.wasm_alloc(4 * n), valuesPtr = e.wasm_alloc(8 * n);
    new Uint32Array(this.fmu.state.memory.buffer, vrPtr, n).set(vrs.map((v) => v.valueReference));
    const write = (values) => {
      if (values.length !== n) throw new FMIError(`${n} values are needed, got ${values.length}`);
      new Float64Array(this.fmu.state.memory.buffer, valuesPtr, n).set(values);
      this.check(e.wasm_set_reals(this.h, vrPtr, n, valuesPtr), "set");
    };
    write.free = () => { e.wasm_free(vrPtr); e.wasm_free(valuesPtr); };
    return write;
  }

  // A reader of directional derivatives (fmi2GetDirectionalDerivative) of the Real variables
  // `unknowns` with respect to `knowns`: d(seed) -> Float64Array (J * seed, one FMI call),
  // d.jacobian() -> [rows of J] (one call per column, unit seeds); d.free() releases its arrays.
  directional(unknowns, knowns) {
    const e = this.fmu.exports, nu = unknowns.length, nk = knowns.length;
    const refs = (names) => names.map((name) => {
      const v = this.variableOf(name);
      if (v.type !== "Real") throw new FMIError(`${v.name} is not a Real variable`);
      return v.valueReference;
    });
    const u = refs(unknowns), k = refs(knowns);
    const uPtr = e.wasm_alloc(4 * nu), kPtr = e.wasm_alloc(4 * nk);
    const seedPtr = e.wasm_alloc(8 * nk), outPtr = e.wasm_alloc(8 * nu);
    new Uint32Array(this.fmu.state.memory.buffer, uPtr, nu).set(u);
    new Uint32Array(this.fmu.state.memory.buffer, kPtr, nk).set(k);
    const d = (seed) => {
      if (seed.length !== nk) throw new FMIError(`a seed of ${nk} values is needed, got ${seed.length}`);
      new Float64Array(this.fmu.state.memory.buffer, seedPtr, nk).set(seed);
      this.check(e.wasm_directional(this.h, uPtr, nu, kPtr, nk, seedPtr, outPtr), "fmi2GetDirectionalDerivative");
      return new Float64Array(this.fmu.state.memory.buffer, outPtr, nu).slice();
    };
    d.jacobian = () => {
      const rows = unknowns.map(() => new Array(nk)), seed = new Float64Array(nk);
      for (let j = 0; j < nk; j++) {
        seed.fill(0);
        seed[j] = 1;
        const column = d(seed);
        for (let i = 0; i < nu; i++) rows[i][j] = column[i];
      }
      return rows;
    };
    d.free = () => { for (const ptr of [uPtr, kPtr, seedPtr, outPtr]) e.wasm_free(ptr); };
    return d;
  }

  setupExperiment({ tolerance, startTime = 0, stopTime } = {}) {
    this.time = startTime;
    return this.check(this.fmu.exports.wasm_setup_experiment(
      this.h, tolerance !== undefined ? 1 : 0, tolerance ?? 0, startTime, stopTime !== undefined ? 1 : 0,
      stopTime ?? 0), "fmi2SetupExperiment");
  }

  enterInitializationMode() {
    return this.check(this.fmu.exports.wasm_enter_initialization_mode(this.h), "fmi2EnterInitializationMode");
  }

  exitInitializationMode() {
    return this.check(this.fmu.exports.wasm_exit_initialization_mode(this.h), "fmi2ExitInitializationMode");
  }

  // One communication step from t to t + h: the status (0 OK, 1 Warning, 2 Discard: the
  // integration failed, see lastSuccessfulTime and terminated); FMIError on Error or Fatal.
  doStep(t, h, noSetFMUStatePriorToCurrentPoint = true) {
    const status = this.check(this.fmu.exports.wasm_do_step(this.h, t, h, noSetFMUStatePriorToCurrentPoint ? 1 : 0),
                              "fmi2DoStep");
    if (status <= 1) this.time = t + h;
    return status;
  }

  get lastSuccessfulTime() {
    const value = this.fmu.exports.wasm_get_real_status(this.h, FMI2_LAST_SUCCESSFUL_TIME);
    this.check(this.fmu.exports.wasm_last_status(), "fmi2GetRealStatus");
    return value;
  }

  get terminated() {
    const value = this.fmu.exports.wasm_get_boolean_status(this.h, FMI2_TERMINATED);
    this.check(this.fmu.exports.wasm_last_status(), "fmi2GetBooleanStatus");
    return value !== 0;
  }

  getFMUState() {
    const s = this.fmu.exports.wasm_get_fmu_state(this.h);
    this.check(this.fmu.exports.wasm_last_status(), "fmi2GetFMUstate");
    return s;
  }

  setFMUState(state) { return this.check(this.fmu.exports.wasm_set_fmu_state(this.h, state), "fmi2SetFMUstate"); }

  freeFMUState(state) { return this.check(this.fmu.exports.wasm_free_fmu_state(this.h, state), "fmi2FreeFMUstate"); }

  terminate() { return this.check(this.fmu.exports.wasm_terminate(this.h), "fmi2Terminate"); }

  reset() { return this.check(this.fmu.exports.wasm_reset(this.h), "fmi2Reset"); }

  free() {
    if (this.c) this.fmu.exports.wasm_free_instance(this.c);
    this.log.push(...this.fmu.readLog());
    this.c = 0;
  }

  // A whole Co-Simulation run as FMPy's simulate_fmu does it (the same FMI calls, so the same
  // numbers as `cosim simulate`): start values, initialization, then communication points
  // startTime + k*stepSize (the last step shortened to stopTime), the outputs after each step.
  // inputs(t) -> {name: value} (optional) is applied before each step.
  // Returns {time: Float64Array, names, values: [Float64Array per name], status, seconds}.
  simulate({ startTime, stopTime, stepSize, tolerance, startValues = {}, outputs, inputs } = {}) {
    const d = this.fmu.defaultExperiment;
    startTime = startTime ?? d.startTime ?? 0;
    stopTime = stopTime ?? d.stopTime ?? startTime + 1;
    stepSize = stepSize ?? d.stepSize ?? (stopTime - startTime) / 500;
    tolerance = tolerance ?? d.tolerance;
    outputs = outputs || this.fmu.names("output");
    if (!(stepSize > 0)) throw new FMIError(`stepSize must be > 0, got ${stepSize}`);
    const isclose = (a, b) => Math.abs(a - b) <= 1e-9 * Math.max(Math.abs(a), Math.abs(b));
    this.setupExperiment({ tolerance, startTime, stopTime });
    this.set(startValues);
    this.enterInitializationMode();
    if (inputs) this.set(inputs(startTime));
    this.exitInitializationMode();
    const read = this.reader(outputs);
    const rows = Math.floor((stopTime - startTime) / stepSize + 1e-9) + 2;
    const time = new Float64Array(rows), values = outputs.map(() => new Float64Array(rows));
    const record = (k, t) => {
      time[k] = t;
      const row = read();
      for (let j = 0; j < row.length; j++) values[j][k] = row[j];
    };
    let t = startTime, n = 0, k = 0, status = 0, seconds;
    try {
      record(k++, t);
      const started = performance.now();
      while (!(t > stopTime || isclose(t, stopTime))) {
        const regular = startTime + (n + 1) * stepSize;
        let next = regular;
        if (next > stopTime && !isclose(next, stopTime)) next = stopTime;
        if (inputs) this.set(inputs(t));
        status = this.doStep(t, next - t);
        if (status === 2) {  // Discard: the FMU's integrator failed; keep what was computed
          if (this.terminated) { t = this.lastSuccessfulTime; record(k++, t); }
          break;
        }
        t = next;
        record(k++, t);
        if (isclose(t, regular)) n++;
      }
      seconds = (performance.now() - started) / 1000;
    } finally {
      read.free();
    }
    this.terminate();
    return { time: time.slice(0, k), names: outputs, values: values.map((v) => v.slice(0, k)), status, seconds };
  }
}
