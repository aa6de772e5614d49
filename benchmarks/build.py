"""Build speed, measured side by side with a baseline in the same run.

Parts (each measurement runs in a fresh Python process, so that imports and caches count as
they do for a user; the baseline and the current tree alternate, ROUNDS times, medians):

1. every exported model from clean (``build(jobs=2)`` into an empty folder) and the no-op
   rebuild that follows, once more with empty user caches (a machine that never built); one
   small model (``Bicycle.Control.PD``) from clean; every exported model of both trees simulated
   (FMPy, CS and ME): the largest difference of the results (target: <= 1e-12);
2. a generated model of N states (a chain of N/2 masses between springs and dampers, written
   as components and ``connect()``, the style of the component bicycle) at N = 500 ... 3000:
   flatten, make_explicit and the full build, and the cost per state (≈ constant if linear);
3. the component bicycles against the flat oracle models (unchanged from before).

Each target of docs/benchmarks.md (clean <= 5 s, no-op <= 0.3 s, the 3000-state model <= 30 s) is printed
with "meets" or "MISSES". The baseline is the committed tree (``git archive``) of ``--baseline`` (default ``HEAD``);
``--baseline none`` skips it. Times are wall [s] and CPU [s] (this process and its children:
gcc, pool workers), as the machine may be shared.

    python benchmarks/build.py [--baseline REF] [--rounds N] [--sizes 500,1000,2000,3000]
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

from side_by_side import baseline_tree, verdict


ROOT = Path(__file__).resolve().parents[1]
ORACLE_LIBRARY = ROOT / "tests" / "oracle"
ROUNDS = 3
SIZES = (500, 1000, 2000, 3000)
SMALL_MODEL = "Bicycle.Control.PD"
# The targets of docs/benchmarks.md (wall seconds on this project's 2-core machines)
CLEAN_TARGET, NOOP_TARGET, CHAIN_STATES, CHAIN_TARGET = 5.0, 0.3, 3000, 30.0


# --- the generated model ---------------------------------------------------------------------

def write_chain_library(folder: Path, states: int) -> str:
    """Write the package ``GeneratedChain`` (MSL layout: one class per file, ``package.order``)
    with the model ``Chain``: a wall, ``states // 2`` masses (2 states each) joined by
    spring-dampers, a free end. Returns the model's full name."""
    n = states // 2
    pkg = folder / "GeneratedChain"
    pkg.mkdir(parents=True, exist_ok=True)
    classes = {
        "Flange": '''
            connector Flange "Translational flange"
              Real s(unit = "m") "Position";
              Real v(unit = "m/s") "Velocity";
              flow Real f(unit = "N") "Force into the component";
            end Flange;''',
        "Mass": '''
            model Mass "Point mass sliding on a line"
              parameter Real m(unit = "kg") = 1 "Mass";
              parameter Real s0(unit = "m") = 0 "Initial position";
              Flange a "Left flange";
              Flange b "Right flange";
              Real s(unit = "m", start = s0, fixed = true) "Position";
              Real v(unit = "m/s", start = 0, fixed = true) "Velocity";
            equation
              a.s = s;
              b.s = s;
              a.v = v;
              b.v = v;
              der(s) = v;
              m * der(v) = a.f + b.f;
            end Mass;''',
        "SpringDamper": '''
            model SpringDamper "Linear spring and damper in parallel"
              parameter Real c(unit = "N/m") = 100 "Stiffness";
              parameter Real d(unit = "N.s/m") = 0.5 "Damping coefficient";
              Flange a "Left flange";
              Flange b "Right flange";
              Real f(unit = "N") "Tension";
            equation
              f = c * (b.s - a.s) + d * (b.v - a.v);
              a.f = f;
              b.f = -f;
            end SpringDamper;''',
        "Fixed": '''
            model Fixed "Flange fixed at the origin"
              Flange a "Flange";
            equation
              a.s = 0;
              a.v = 0;
            end Fixed;''',
        "Free": '''
            model Free "Flange without force"
              Flange a "Flange";
            equation
              a.f = 0;
            end Free;''',
    }
    lines = [f'model Chain "{n} masses between springs and dampers ({2 * n} states)"\n',
             '  Fixed fixed "Wall";\n  Free free "Free end";\n']
    lines += [f'  Mass m{k}(s0 = {0.001 * k!r}) "Mass {k}";\n  SpringDamper e{k} "Spring-damper {k}";\n'
              for k in range(1, n + 1)]
    lines.append(f'  output Real tip(unit = "m") = m{n}.s "Position of the last mass";\nequation\n')
    lines.append("  connect(fixed.a, e1.a);\n")
    for k in range(1, n + 1):
        lines.append(f"  connect(e{k}.b, m{k}.a);\n")
        lines.append(f"  connect(m{k}.b, e{k + 1}.a);\n" if k < n else f"  connect(m{k}.b, free.a);\n")
    lines.append("  annotation(experiment(StopTime = 1));\nend Chain;")
    (pkg / "package.mo").write_text(
        'within;\npackage GeneratedChain "Generated by benchmarks/build.py: a chain of masses, springs and dampers"\n'
        "end GeneratedChain;\n")
    for name, text in {**classes, "Chain": "".join(lines)}.items():
        (pkg / f"{name}.mo").write_text("within GeneratedChain;\n" + textwrap.dedent(text).strip() + "\n")
    (pkg / "package.order").write_text("".join(f"{name}\n" for name in (*classes, "Chain")))
    return "GeneratedChain.Chain"


# --- one measurement in a fresh process ------------------------------------------------------

# Runs in the child: ``root`` first on sys.path (the tree measured), prints one JSON line.
CHILD = r'''
import json, resource, sys, time
sys.path.insert(0, sys.argv[1])
task = json.loads(sys.argv[2])

def cpu():
    s, c = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return s.ru_utime + s.ru_stime + c.ru_utime + c.ru_stime

t0, c0 = time.perf_counter(), cpu()
from cosim.compiler.build import build, build_model
from cosim.compiler.library import load_library
out = {}
if task["kind"] == "all":
    build(output=task["out"], jobs=2)
    out["clean"] = [time.perf_counter() - t0, cpu() - c0]
    t1, c1 = time.perf_counter(), cpu()
    again = build(output=task["out"], jobs=2)
    assert not any(r.rebuilt for r in again), "the no-op build rebuilt something"
    out["noop"] = [time.perf_counter() - t1, cpu() - c1]
elif task["kind"] == "one":
    library = load_library(task.get("library"))
    t1, c1 = time.perf_counter(), cpu()
    build_model(task["model"], task["out"], library)
    out["first"] = [time.perf_counter() - t1, cpu() - c1]
    t2, c2 = time.perf_counter(), cpu()
    build_model(task["model"], task["out"], library, force=True)
    out["again"] = [time.perf_counter() - t2, cpu() - c2]
elif task["kind"] == "phases":
    from cosim.compiler.flatten import flatten
    from cosim.compiler.ode import make_explicit
    library = load_library(task["library"])
    t1, c1 = time.perf_counter(), cpu()
    flat = flatten(library, task["model"])
    t2, c2 = time.perf_counter(), cpu()
    explicit = make_explicit(flat)
    t3, c3 = time.perf_counter(), cpu()
    build_model(task["model"], task["out"], library)
    t4, c4 = time.perf_counter(), cpu()
    out = {"flatten": [t2 - t1, c2 - c1], "explicit": [t3 - t2, c3 - c2], "build": [t4 - t3, c4 - c3],
           "states": explicit.x.numel()}
print(json.dumps(out))
'''


def measure(root: Path, task: dict, scratch: Path) -> dict:
    """Run ``task`` against the tree ``root`` in a fresh process, into an empty output folder; with
    ``task["cold"]`` also with empty user caches (``XDG_CACHE_HOME``: pymoca's parse cache, the
    compiled runtime, the library index), as on a machine that never built anything."""
    with tempfile.TemporaryDirectory(dir=scratch) as out, tempfile.TemporaryDirectory(dir=scratch) as cache:
        env = {k: v for k, v in os.environ.items() if k not in ("COSIM_FMU_DIR", "COSIM_MODELICA_PATH")}
        if task.get("cold"):
            env["XDG_CACHE_HOME"] = cache
        result = subprocess.run([sys.executable, "-c", CHILD, str(root), json.dumps({**task, "out": out})],
                                capture_output=True, text=True, env=env, cwd=scratch)
    if result.returncode != 0:
        raise RuntimeError(f"measurement {task} in {root} failed:\n{result.stderr[-3000:]}")
    return json.loads(result.stdout.strip().splitlines()[-1])


def medians(runs: list[dict]) -> dict:
    keys = [k for k in runs[0] if isinstance(runs[0][k], list)]
    return {k: [statistics.median(r[k][i] for r in runs) for i in (0, 1)] for k in keys}


def side_by_side(trees: dict[str, Path], task: dict, rounds: int, scratch: Path) -> dict[str, dict]:
    """Medians of ``rounds`` alternating runs of ``task`` in each tree."""
    runs: dict[str, list] = {label: [] for label in trees}
    for _ in range(rounds):
        for label, root in trees.items():
            runs[label].append(measure(root, task, scratch))
    return {label: medians(r) for label, r in runs.items()}


def report(title: str, results: dict[str, dict], keys: list[str]) -> None:
    print(title)
    for key in keys:
        cells = [f"{label} {results[label][key][0]:7.2f} s wall {results[label][key][1]:7.2f} s CPU"
                 for label in results]
        ratio = ""
        if "baseline" in results and "current" in results:
            b, c = results["baseline"][key], results["current"][key]
            ratio = f"   current/baseline: {c[0] / b[0]:5.2f}x wall {c[1] / b[1]:5.2f}x CPU"
        print(f"  {key:8s} " + " | ".join(cells) + ratio)


def same_results(trees: dict[str, Path], scratch: Path) -> None:
    """Every exported model built by both trees, simulated by FMPy (Co-Simulation and Model
    Exchange, 3 s, a small initial roll where the model has phi0): the largest difference of any
    output (by name) relative to max(1, |output|), and whether all are bit for bit the same."""
    import fmpy
    import numpy as np

    folders = {}
    for label, root in trees.items():
        folders[label] = scratch / f"same-{label}"
        code = (f"import sys; sys.path.insert(0, {str(root)!r}); from cosim.compiler.build import build; "
                f"build(output={str(folders[label])!r}, jobs=2)")
        subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, cwd=scratch,
                       env={k: v for k, v in os.environ.items() if k not in ("COSIM_FMU_DIR", "COSIM_MODELICA_PATH")})
    worst, identical, runs = 0.0, True, 0
    for before in sorted(folders["baseline"].glob("*.fmu")):
        after = folders["current"] / before.name
        names = {v.name for v in fmpy.read_model_description(str(before)).modelVariables}
        start = {"phi0": 0.02} if "phi0" in names else {}
        for kind in ("CoSimulation", "ModelExchange"):
            # compared by name: the outputs of a model may be listed in another order by the two trees
            ra, rb = (fmpy.simulate_fmu(str(f), stop_time=3.0, output_interval=0.01, fmi_type=kind,
                                        start_values=start) for f in (before, after))
            common = [n for n in ra.dtype.names if n in rb.dtype.names]
            a, b = (np.array([r[n] for n in common], dtype=float) for r in (ra, rb))
            runs += 1
            same_shape = a.shape == b.shape and len(common) == len(ra.dtype.names) == len(rb.dtype.names)
            identical &= same_shape and np.array_equal(a, b)
            worst = max(worst, float(np.max(np.abs(a - b) / np.maximum(1.0, np.abs(a)))) if a.shape == b.shape else np.inf)
    print(f"results of the FMUs of both trees ({runs} runs: every exported model, CS and ME, 3 s): largest "
          f"relative difference {worst:.3g}, {'bit for bit identical' if identical else 'not identical'} "
          f"({'meets' if worst <= 1e-12 else 'MISSES'} <= 1e-12)")


def generated(trees: dict[str, Path], sizes: list[int], baseline_sizes: list[int], rounds: int,
              scratch: Path) -> dict[int, float]:
    built = {}
    print("generated chain model: flatten, make_explicit, and the full build (which flattens again: "
          f"cosim build from the library); median of {rounds} (one run above 1000 states); "
          "full build per 1000 states in brackets")
    for states in sizes:
        library = scratch / f"chain{states}"
        model = write_chain_library(library, states)
        task = {"kind": "phases", "model": model, "library": str(library)}
        chosen = {k: v for k, v in trees.items() if k == "current" or states in baseline_sizes}
        results = side_by_side(chosen, task, rounds if states <= 1000 else 1, scratch)
        for label, t in results.items():
            print(f"  {states:5d} states {label:8s} flatten {t['flatten'][0]:6.2f} s  explicit "
                  f"{t['explicit'][0]:6.2f} s  build {t['build'][0]:6.2f} s (CPU {t['build'][1]:6.2f} s)  "
                  f"[{1000 * t['build'][0] / states:5.2f} s per 1000 states]")
        built[states] = results["current"]["build"][0]
        if len(results) == 2:
            print(f"  {'':20s}current/baseline build: {results['current']['build'][0] / results['baseline']['build'][0]:5.2f}x")
    return built


def component_versus_oracle(out: Path, name: str = "Whipple") -> None:
    """Seconds for flatten, make_explicit and the full build (C + gcc + FMU) of the component model
    ``Bicycle.Bicycles.NAME`` and the oracle ``BicycleOracle.NAME``, best of 2, in this process."""
    from cosim.compiler.build import build_model
    from cosim.compiler.flatten import flatten
    from cosim.compiler.library import load_library
    from cosim.compiler.ode import make_explicit

    COMPONENT = ("component", f"Bicycle.Bicycles.{name}", None)
    ORACLE = ("oracle (flat, generated)", f"BicycleOracle.{name}", ORACLE_LIBRARY)
    best: dict[str, dict[str, float]] = {}
    for _ in range(2):
        for label, model, path in (COMPONENT, ORACLE):
            library = load_library(str(path) if path else None)
            t0 = time.perf_counter()
            flat = flatten(library, model)
            t1 = time.perf_counter()
            explicit = make_explicit(flat)
            t2 = time.perf_counter()
            build_model(model, out, library, force=True)
            t3 = time.perf_counter()
            times = {"flatten": t1 - t0, "make_explicit": t2 - t1, "build": t3 - t2,
                     "equations": float(len(flat.casadi.equations)), "states": float(explicit.x.numel())}
            old = best.setdefault(label, times)
            for key, value in times.items():
                old[key] = min(old[key], value)
    c, o = best[COMPONENT[0]], best[ORACLE[0]]
    print(f"{name:26s} {'flat eqs':>9s} {'flatten':>9s} {'explicit':>9s} {'build':>9s}")
    for label, t in ((COMPONENT[0], c), (ORACLE[0], o)):
        print(f"{label:26s} {t['equations']:9.0f} {t['flatten']:8.2f}s {t['make_explicit']:8.2f}s {t['build']:8.2f}s")
    print(f"{'ratio component/oracle':26s} {c['equations'] / o['equations']:8.2f}x {c['flatten'] / o['flatten']:8.2f}x "
          f"{c['make_explicit'] / o['make_explicit']:8.2f}x {c['build'] / o['build']:8.2f}x")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", default="HEAD", help="git ref of the baseline, or 'none' (default: HEAD)")
    parser.add_argument("--rounds", type=int, default=ROUNDS, help=f"repetitions, medians (default: {ROUNDS})")
    parser.add_argument("--sizes", default=",".join(map(str, SIZES)), help="states of the generated models")
    parser.add_argument("--baseline-sizes", default="500",
                        help="generated sizes also built by the baseline (its cost grows quadratically)")
    parser.add_argument("--skip-oracle", action="store_true", help="skip the component-vs-oracle part")
    args = parser.parse_args()
    sizes = [int(s) for s in args.sizes.split(",") if s]
    baseline_sizes = [int(s) for s in args.baseline_sizes.split(",") if s]
    with tempfile.TemporaryDirectory(prefix="cosim-bench-") as tmp:
        scratch = Path(tmp)
        trees = {"current": ROOT}
        if args.baseline != "none":
            trees = {"baseline": baseline_tree(args.baseline, scratch / "baseline"), **trees}
        print(f"median of {args.rounds} alternating runs, each in a fresh process; "
              f"baseline: {args.baseline}\n")
        all_models = side_by_side(trees, {"kind": "all"}, args.rounds, scratch)
        report("every exported model from clean (an empty output folder; the user caches warm as after any "
               "earlier build), then no-op (build(jobs=2))", all_models, ["clean", "noop"])
        report("the same on a machine that never built anything (empty XDG_CACHE_HOME: pymoca parses the "
               "library, the runtime is compiled)",
               side_by_side(trees, {"kind": "all", "cold": True}, 1, scratch), ["clean"])
        verdict("clean build of every exported model", all_models["current"]["clean"][0], CLEAN_TARGET)
        verdict("no-op build", all_models["current"]["noop"][0], NOOP_TARGET)
        report(f"one small model ({SMALL_MODEL}, in-process): first build into an empty folder, then "
               "a forced rebuild (the runtime object cached by the first)",
               side_by_side(trees, {"kind": "one", "model": SMALL_MODEL}, args.rounds, scratch), ["first", "again"])
        if "baseline" in trees:
            same_results(trees, scratch)
        print()
        chain = generated(trees, sizes, baseline_sizes, args.rounds, scratch)
        if CHAIN_STATES in chain:
            verdict(f"{CHAIN_STATES}-state generated model", chain[CHAIN_STATES], CHAIN_TARGET)
        print()
        if not args.skip_oracle:
            for name in ("Whipple", "WhippleRider"):
                component_versus_oracle(scratch / name, name)
                print()


if __name__ == "__main__":
    main()
