// viewstate.js -- what the eigenvalue view of `cosim app` saves, loads and puts in the page's
// address (cosim/app/export.py bundles it before app.js, which applies what it returns).
//
// A view is {bicycle, parameters (every parameter of the bicycle, SI units), speed [m/s],
// speedRange {min, max} [m/s], reRange {min, max} [1/s] or null (the axes fit the eigenvalues)}.
//
//   CosimViewState.toFile(view)               // the JSON text of a parameter file
//   CosimViewState.fromFile(text, bicycles)   // {view} or {message} naming the bad field
//   CosimViewState.toHash(view, bicycles)     // "bicycle=...&v=...&vmin=...&vmax=...&re=fit&mB=90"
//   CosimViewState.fromHash(hash, bicycles)   // {view}, {message}, or null for an empty hash
//   CosimViewState.range(lowText, highText, fit)  // {range} (null: fit) or {message, field}
//
// `bicycles` is COSIM_DATA.bicycles. The file has a format name and a version; a parameter the
// file leaves out keeps the bicycle's own value (a hand-written file may give only what it
// changes); the address gives only the parameters that differ from the bicycle's own. Numbers
// are written with String(x), which reads back to the same double. What is checked here is the
// file's structure and that every value is a finite number; app.js then applies its parameter
// checks (the editor's) and refuses the whole view with the first problem.
(function () {
  "use strict";

  const FORMAT = "cosim-app-bicycle", VERSION = 1;
  const NUMBER = /^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/;
  const RESERVED = ["bicycle", "v", "vmin", "vmax", "re"];

  const isObject = (x) => x !== null && typeof x === "object" && !Array.isArray(x);
  const finite = (x) => typeof x === "number" && Number.isFinite(x);

  function toFile(view) {
    return JSON.stringify({
      format: FORMAT, version: VERSION, bicycle: view.bicycle, parameters: view.parameters, speed: view.speed,
      speedRange: { min: view.speedRange.min, max: view.speedRange.max },
      reRange: view.reRange ? { min: view.reRange.min, max: view.reRange.max } : null,
    }, null, 2) + "\n";
  }

  // A text field's number, or the reason it is not one.
  function parseNumber(text) {
    const t = String(text).trim();
    if (t === "") return { message: "empty; type a number" };
    if (!NUMBER.test(t)) return { message: `not a number: '${t}'` };
    const x = Number(t);
    return Number.isFinite(x) ? { value: x } : { message: `must be finite, got '${t}'` };
  }

  // The range of two fields; with `fit`, both empty (or "fit") means null (the axes fit).
  function range(lowText, highText, fit) {
    const blank = (t) => String(t).trim() === "" || String(t).trim().toLowerCase() === "fit";
    if (fit && blank(lowText) && blank(highText)) return { range: null };
    const low = parseNumber(lowText), high = parseNumber(highText);
    if (low.message) return { field: "min", message: `from: ${low.message}` };
    if (high.message) return { field: "max", message: `to: ${high.message}` };
    if (!(low.value < high.value)) return { field: "max", message: `from ${low.value} must be less than to ${high.value}` };
    return { range: { min: low.value, max: high.value } };
  }

  // The checks shared by the file and the address: the bicycle exists, its parameters are its
  // own and finite, the ranges are ordered and hold the speed. Messages name the file's field
  // (parameters.mB).
  function check(raw, bicycles) {
    const bicycle = bicycles.find((b) => b.name === raw.bicycle);
    if (!bicycle) {
      return { message: `bicycle: no bicycle '${raw.bicycle}' on this page (it has ${bicycles.map((b) => b.name).join(", ")})` };
    }
    const parameters = { ...bicycle.parameters };
    for (const [k, x] of Object.entries(raw.parameters)) {
      if (!(k in bicycle.parameters)) return { message: `parameters.${k}: not a parameter of ${bicycle.name}` };
      if (!finite(x)) return { message: `parameters.${k}: not a finite number (got ${JSON.stringify(x)})` };
      parameters[k] = x;
    }
    const sr = raw.speedRange || { min: bicycle.speeds.min, max: bicycle.speeds.max };
    for (const k of ["min", "max"]) if (!finite(sr[k])) return { message: `speedRange.${k}: not a finite number (got ${JSON.stringify(sr[k])})` };
    if (!(sr.min < sr.max)) return { message: `speedRange: min ${sr.min} must be less than max ${sr.max}` };
    const rr = raw.reRange;
    if (rr !== null && rr !== undefined) {
      for (const k of ["min", "max"]) if (!finite(rr[k])) return { message: `reRange.${k}: not a finite number (got ${JSON.stringify(rr[k])})` };
      if (!(rr.min < rr.max)) return { message: `reRange: min ${rr.min} must be less than max ${rr.max}` };
    }
    const speed = raw.speed === undefined ? Math.min(Math.max(bicycle.speeds.default, sr.min), sr.max) : raw.speed;
    if (!finite(speed)) return { message: `speed: not a finite number (got ${JSON.stringify(speed)})` };
    if (speed < sr.min || speed > sr.max) return { message: `speed: ${speed} m/s lies outside the speed range ${sr.min} to ${sr.max} m/s` };
    return { view: { bicycle: bicycle.name, parameters, speed, speedRange: { min: sr.min, max: sr.max },
                     reRange: rr ? { min: rr.min, max: rr.max } : null } };
  }

  function fromFile(text, bicycles) {
    let raw;
    try { raw = JSON.parse(text); } catch (e) { return { message: `not a JSON file (${e.message})` }; }
    if (!isObject(raw)) return { message: "not a parameter file: the JSON is not an object" };
    if (raw.format !== FORMAT) return { message: `format: expected "${FORMAT}", got ${JSON.stringify(raw.format)}` };
    if (raw.version !== VERSION) return { message: `version: ${JSON.stringify(raw.version)} is not one this page reads (${VERSION})` };
    if (typeof raw.bicycle !== "string") return { message: `bicycle: expected a name, got ${JSON.stringify(raw.bicycle)}` };
    if (raw.parameters !== undefined && !isObject(raw.parameters)) return { message: "parameters: expected an object of name: value" };
    if (raw.speedRange !== undefined && !isObject(raw.speedRange)) return { message: "speedRange: expected {min, max}" };
    if (raw.reRange !== undefined && raw.reRange !== null && !isObject(raw.reRange)) return { message: "reRange: expected {min, max} or null" };
    const known = new Set(["format", "version", "bicycle", "parameters", "speed", "speedRange", "reRange"]);
    const unknown = Object.keys(raw).filter((k) => !known.has(k));
    if (unknown.length) return { message: `${unknown[0]}: not a field of a parameter file (${[...known].join(", ")})` };
    return check({ ...raw, parameters: raw.parameters || {} }, bicycles);
  }

  function toHash(view, bicycles) {
    const bicycle = bicycles.find((b) => b.name === view.bicycle);
    const q = new URLSearchParams();
    q.set("bicycle", view.bicycle);
    q.set("v", String(view.speed));
    q.set("vmin", String(view.speedRange.min));
    q.set("vmax", String(view.speedRange.max));
    q.set("re", view.reRange ? `${view.reRange.min},${view.reRange.max}` : "fit");
    for (const [k, x] of Object.entries(view.parameters)) {
      if (!bicycle || bicycle.parameters[k] !== x) q.set(k, String(x));
    }
    return q.toString();
  }

  function fromHash(hash, bicycles) {
    const text = String(hash || "").replace(/^#/, "");
    if (text === "") return null;
    const q = new URLSearchParams(text);
    const name = q.get("bicycle");
    if (name === null) return { message: "bicycle: the address names no bicycle" };
    const bicycle = bicycles.find((b) => b.name === name);
    if (!bicycle) return check({ bicycle: name, parameters: {} }, bicycles);
    const number = (key) => {
      const p = parseNumber(q.get(key));
      return p.message ? { message: `${key}: ${p.message}` } : p;
    };
    const raw = { bicycle: name, parameters: {} };
    for (const [key] of q) {
      if (RESERVED.includes(key)) continue;
      if (!(key in bicycle.parameters)) return { message: `${key}: not a parameter of ${name}` };
      const p = number(key);
      if (p.message) return p;
      raw.parameters[key] = p.value;
    }
    if (q.has("vmin") || q.has("vmax")) {
      const r = range(q.get("vmin") ?? "", q.get("vmax") ?? "", false);
      if (r.message) return { message: `vmin, vmax: ${r.message}` };
      raw.speedRange = r.range;
    }
    if (q.has("re") && q.get("re").trim() !== "fit") {
      const parts = q.get("re").split(",");
      const r = parts.length === 2 ? range(parts[0], parts[1], false) : { message: "expected 'fit' or MIN,MAX" };
      if (r.message) return { message: `re: ${r.message}` };
      raw.reRange = r.range;
    }
    if (q.has("v")) {
      const p = number("v");
      if (p.message) return p;
      raw.speed = p.value;
    }
    return check(raw, bicycles);
  }

  window.CosimViewState = { toFile, fromFile, toHash, fromHash, range, parseNumber, FORMAT, VERSION };
})();
