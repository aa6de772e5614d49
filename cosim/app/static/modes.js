// modes.js -- the names of the bicycle's modes in the eigenvalue view of `cosim app`
// (cosim/app/export.py bundles it before app.js): weave, capsize and castering, as the paper
// (Figure 9) and BicycleParameters name them, and the read-outs that print them.
//
//   CosimModes.name(ev, v)        // ev: [[re, im] x 4] sorted by real part; the mode of each, or null
//   CosimModes.readout(ev, v)     // "weave 0.413 ± 3.079i, capsize -1.429, castering -12.159"
//   CosimModes.value(re, im)      // one eigenvalue as the read-outs print it
//
// How a mode is recognised at one speed, from the four eigenvalues alone (no tracking over the
// sweep, so the plot, the read-outs and the tests agree point by point):
// - an oscillatory pair with two real eigenvalues beside it: the pair is the weave, the more
//   negative real one castering, the other capsize (it crosses zero at the capsize speed);
// - four real eigenvalues (below the speed where the weave pair forms): the two largest are the
//   weave's (they join into its pair), the next capsize, the smallest castering;
// - two oscillatory pairs (the riderless bicycle at low speed, where capsize and castering have
//   joined): the pair with the larger real part is the weave, the other "capsize + castering".
// Riding backwards (v < 0) the modes are not named: they are the forward bicycle's names.
(function () {
  "use strict";

  // |Im| below this counts as real (as app.js and cosim.analytic.whipple._imag_tol).
  const oscillatory = (re, im) => Math.abs(im) > 1e-7 * Math.max(1, Math.hypot(re, im));

  const DIGITS = 3;  // decimals of the read-outs [1/s]

  function name(ev, v) {
    const out = ev.map(() => null);
    if (!(v >= 0) || ev.length !== 4) return out;
    const byRe = (a, b) => ev[a][0] - ev[b][0];
    const osc = [], real = [];
    ev.forEach(([re, im], i) => (oscillatory(re, im) ? osc : real).push(i));
    osc.sort(byRe); real.sort(byRe);
    if (osc.length === 2 && real.length === 2) {
      for (const i of osc) out[i] = "weave";
      out[real[0]] = "castering"; out[real[1]] = "capsize";
    } else if (real.length === 4) {
      out[real[0]] = "castering"; out[real[1]] = "capsize"; out[real[2]] = out[real[3]] = "weave";
    } else if (osc.length === 4) {
      for (const i of osc.slice(0, 2)) out[i] = "capsize + castering";
      for (const i of osc.slice(2)) out[i] = "weave";
    }
    return out;
  }

  const fixed = (x) => (Math.abs(x) < 0.5 * 10 ** -DIGITS ? 0 : x).toFixed(DIGITS);

  function value(re, im) {
    return oscillatory(re, im) ? `${fixed(re)} \u00b1 ${fixed(Math.abs(im))}i` : fixed(re);
  }

  // Every eigenvalue once (a pair as one "re ± imi"), grouped by mode in the order weave,
  // capsize, castering; unnamed ones as "eigenvalues ...".
  function readout(ev, v) {
    const names = name(ev, v), groups = new Map();
    ev.forEach(([re, im], i) => {
      if (oscillatory(re, im) && im < 0) return;  // a pair: printed once, from its + member
      const key = names[i] || "eigenvalues";
      if (!groups.has(key)) groups.set(key, []);
      groups.get(key).push(value(re, im));
    });
    const order = ["weave", "capsize", "castering", "capsize + castering", "eigenvalues"];
    return order.filter((k) => groups.has(k)).map((k) => {
      const values = groups.get(k);
      return k === "weave" && values.length === 2 ? `weave (still real) ${values.join(" and ")}` : `${k} ${values.join(", ")}`;
    }).join("; ");
  }

  window.CosimModes = { name, readout, value, oscillatory, DIGITS };
})();
