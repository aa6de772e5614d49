"""The matrix report: ``report.md``, ``report.html`` and one PNG per study (heat map or strip).

Every file is written under a temporary name and renamed when complete (:mod:`cosim.outputs`):
a kill while reporting never leaves a truncated report under its final name.
"""
from __future__ import annotations

import html
import json
import math
import sys
from pathlib import Path

from cosim.cosimulation import registry
from cosim.errors import CosimError, OutputError
from cosim.fmu.parameters import declarations
from cosim.outputs import atomic_output, write_text

ORDER = {"failed": 0, "disagree": 1, "marginal": 2, "agree": 3, "observed": 3}
# Okabe-Ito colours, told apart by colour-blind readers: blue stable, orange and vermilion unstable
COLORS = {"stable": "#0072B2", "unstable": "#E69F00", "fell": "#D55E00", "diverged": "#CC79A7",
          "marginal": "#999999", "unexcited": "#56B4E9", None: "#000000"}
#: The heat map's diverging colour map of the observed growth rate: blue (decays) - white - orange (grows).
GROWTH_COLORS = ("#2166AC", "#F7F7F7", "#E66101")


def _num(v, fmt="{:.4g}"):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "-"
    return fmt.format(v)


def _row(rec: dict) -> dict:
    pred = rec.get("prediction") or {}
    obs = rec.get("observed") or {}
    out = rec.get("outcome") or {}
    notes = []
    if pred.get("tuned"):
        notes.append(", ".join(f"{k} = {v:.4g}" for k, v in pred["tuned"].items()))
    if obs.get("extended"):
        notes.append("re-run longer")
    if rec.get("error"):
        notes.append(rec["error"])
    outcome = out.get("status", "-")
    if outcome in ("fell", "diverged"):
        outcome += f" at {out.get('time', 0):.2f} s"
    return {
        "case": rec["label"], "max_re": _num(pred.get("max_re")), "predicted": pred.get("class", "-"),
        "observed": obs.get("class") or "-", "growth": _num(obs.get("growth_rate")),
        "max_roll": _num(obs.get("max_roll")), "settling": _num(obs.get("settling_time"), "{:.2f}"),
        "outcome": outcome, "agreement": rec.get("agreement") or "-", "notes": "; ".join(notes),
    }


COLUMNS = [("case", "case"), ("max_re", "predicted max Re [1/s]"), ("predicted", "predicted"),
           ("observed", "observed"), ("growth", "growth rate [1/s]"), ("max_roll", "max abs(x)"),
           ("settling", "settling time [s]"), ("outcome", "outcome"), ("agreement", "agreement"), ("notes", "notes")]


def _sorted(records):
    return sorted(records, key=lambda r: (ORDER.get(r.get("agreement"), 0), r.get("index", 0)))


# --------------------------------------------------------------------------- plots

def _plot_options(study) -> dict:
    return next((p for p in study.plots if "x" in p), {})


def _plot_axes(study, cases):
    p = _plot_options(study)
    if p:
        return p["x"], p.get("y")
    varying = [n for n, vals in study.axes.items() if len(set(map(str, vals))) > 1]
    if not varying:
        varying = [n for n in cases[0].values] if cases else []
    return (varying[0] if varying else None), (varying[1] if len(varying) > 1 else None)


def axis_label(study, name: str, key: str) -> str:
    """``NAME [unit]`` of a plot axis (``key``: ``"x"`` or ``"y"``): the unit the study's plot
    gives (``x_unit``/``y_unit``), else that of the parameter the study sets to ``=NAME`` (of a
    model, or of a Python block's Modelica twin)."""
    unit = _plot_options(study).get(f"{key}_unit") or _parameter_unit(study, name)
    return f"{name} [{unit}]" if unit else f"{name} (no unit declared)"


def _parameter_unit(study, name: str) -> str | None:
    for component in (study.raw.get("components") or {}).values():
        if not isinstance(component, dict):
            continue
        params = [p for p, value in (component.get("parameters") or {}).items() if value == f"={name}"]
        if params:
            try:
                model = component.get("model") or registry.lookup(component.get("python")).twin
                declared = declarations(model, str(component.get("fmi_version", "2"))) if model else {}
            except (CosimError, OSError):  # the report is written whatever the library holds now
                return None
            unit = getattr(declared.get(params[0]), "unit", None)
            if unit:
                return unit
    return None


def plot_study(study, cases, records, path: Path, expected=None) -> Path | None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    by_key = {r["key"]: r for r in records}
    pairs = [(c, by_key[c.key]) for c in cases if c.key in by_key]
    x_name, y_name = _plot_axes(study, [c for c, _ in pairs])
    if not pairs or x_name is None:
        return None
    margin = study.settings["margin"]

    def val(case, name):
        v = case.variables.get(name, case.values.get(name))
        return float(v) if isinstance(v, (int, float)) else math.nan

    options = _plot_options(study)
    fig, ax = plt.subplots(figsize=(9.0, 4.8))
    if y_name:
        from matplotlib.colors import LinearSegmentedColormap, SymLogNorm
        from matplotlib.ticker import FuncFormatter, NullLocator

        xs = np.array([val(c, x_name) for c, _ in pairs])
        ys = np.array([val(c, y_name) for c, _ in pairs])
        # cells: the observed growth rate on a blue/orange diverging map (white: neither grows nor
        # decays); a case without one (it fell or diverged before a rate was measured, or failed)
        # is drawn by its class
        grow = np.array([(r.get("observed") or {}).get("growth_rate") or math.nan for _, r in pairs], float)
        classes = [(r.get("observed") or {}).get("class") for _, r in pairs]
        rated = np.isfinite(grow)
        if rated.any():
            # symmetric log scale: rates near 0 (the boundary) stay told apart beside large ones
            lim = max(float(np.abs(grow[rated]).max()), 2 * margin, 1e-9)
            thresh = min(max(margin, 0.05), lim)
            cmap = LinearSegmentedColormap.from_list("growth", GROWTH_COLORS)
            cells = ax.scatter(xs[rated], ys[rated], s=160, marker="s", c=grow[rated], cmap=cmap,
                               norm=SymLogNorm(thresh, vmin=-lim, vmax=lim), edgecolors="0.6", linewidths=0.4)
            # under the axes: the legend has the space on the right
            bar = fig.colorbar(cells, ax=ax, label="observed growth rate [1/s] (symmetric log scale)",
                               location="bottom", pad=0.2, fraction=0.05, aspect=50)
            # 0 and the decades well outside the linear part, so that no two tick labels touch
            decades = [10.0 ** k for k in range(-6, 7) if 3 * thresh <= 10.0 ** k <= lim]
            bar.set_ticks([-d for d in reversed(decades)] + [0.0] + decades)
            bar.ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
            bar.ax.xaxis.set_minor_locator(NullLocator())
        for cls in ("stable", "unstable", "fell", "diverged", "marginal", "unexcited", None):
            sel = [i for i in range(len(pairs)) if classes[i] == cls and not rated[i]]
            if sel:
                ax.scatter(xs[sel], ys[sel], s=160, marker="s", c=COLORS[cls],
                           label=f"observed {cls or 'failed'} (no growth rate)", edgecolors="none")
        for agreement, marker, color in (("disagree", "x", "black"), ("marginal", "o", "black"),
                                         ("failed", "X", "orange")):
            sel = [i for i, (_, r) in enumerate(pairs) if r.get("agreement") == agreement]
            if sel:
                ax.scatter(xs[sel], ys[sel], s=60, marker=marker, facecolors="none" if marker == "o" else color,
                           edgecolors=color, label=agreement)
        pred = np.array([(r.get("prediction") or {}).get("max_re", math.nan) or math.nan for _, r in pairs], float)
        ok = np.isfinite(pred) & np.isfinite(xs) & np.isfinite(ys)
        if ok.sum() >= 4 and len(set(xs[ok])) > 1 and len(set(ys[ok])) > 1:
            try:
                clipped = np.clip(pred[ok], -5, 5)
                cs = ax.tricontour(xs[ok], ys[ok], clipped, levels=[0.0], colors="black", linewidths=2)
                ax.tricontour(xs[ok], ys[ok], clipped, levels=[-margin, margin], colors="black",
                              linewidths=0.8, linestyles="dashed")
                if any(len(segment) for segment in cs.allsegs[0]):  # listed only where a line is drawn
                    ax.plot([], [], color="black", lw=2, label="predicted boundary (max Re = 0)")
            except Exception:
                pass
        for k, level in enumerate(options.get("hlines", [])):
            ax.axhline(level, color="purple", ls=":", lw=1.2, label=f"{y_name} = {level:g}")
        ax.margins(0.06)
        ax.set_ylabel(axis_label(study, y_name, "y"))
        ax.set_title(f"{study.name}: observed growth rate (cells) and predicted boundary (line)")
    else:
        order = sorted(range(len(pairs)), key=lambda i: val(pairs[i][0], x_name))
        xs = np.array([val(pairs[i][0], x_name) for i in order])
        pred = np.array([((pairs[i][1].get("prediction") or {}).get("max_re") or math.nan) for i in order], float)
        grow = np.array([((pairs[i][1].get("observed") or {}).get("growth_rate") or math.nan) for i in order], float)
        ax.axhspan(-margin, margin, color="#dddddd", label=f"marginal band (|max Re| < {margin:g})")
        ax.axhline(0, color="gray", lw=0.8)
        if np.isfinite(pred).any():
            ax.plot(xs, pred, "-", color="navy", lw=1.5, label="predicted max Re")
        for cls in ("stable", "unstable", "fell", "diverged", "marginal", "unexcited", None):
            sel = [k for k, i in enumerate(order) if (pairs[i][1].get("observed") or {}).get("class") == cls]
            if sel:
                ax.scatter(xs[sel], np.where(np.isfinite(grow[sel]), grow[sel], 0.0), s=36, c=COLORS[cls],
                           zorder=3, label=f"observed growth rate: {cls or 'failed'}")
        sel = [k for k, i in enumerate(order) if pairs[i][1].get("agreement") == "disagree"]
        if sel:
            ax.scatter(xs[sel], np.nan_to_num(grow[sel]), s=90, marker="x", c="black", zorder=4, label="disagree")
        if expected:
            for k, v in enumerate(expected):
                ax.axvline(v, color="green", ls="--", lw=1, label="claimed boundary" if k == 0 else None)
        finite = np.concatenate([pred[np.isfinite(pred)], grow[np.isfinite(grow)]])
        if finite.size:
            lim = min(max(abs(finite).max() * 1.3, 4 * margin), 50)
            ax.set_ylim(-lim, lim)
        ax.set_yscale("symlog", linthresh=max(2 * margin, 0.02))
        ax.set_ylabel("growth rate [1/s] (symlog)")
        ax.set_title(f"{study.name}: predicted max Re vs observed growth")
    ax.set_xlabel(axis_label(study, x_name, "x"))
    if ax.get_legend_handles_labels()[0]:  # beside the axes: it covers no cell
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), framealpha=0.85)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    try:
        with atomic_output(path, "heat map") as tmp:
            fig.savefig(tmp, dpi=110, format="png")
    finally:
        plt.close(fig)
    return path


# --------------------------------------------------------------------------- documents

def _summary(result) -> dict:
    c = result.counts
    return {"name": result.spec.name, "passed": result.passed, **c, "ran": result.ran, "resumed": result.resumed,
            "seconds": round(result.seconds, 2),
            "sample": ({"cases": len(result.cases), "of": result.total, "how": result.sample}
                       if getattr(result, "sample", "") else None),
            "checks": [{"study": ch.study, "kind": ch.kind, "title": ch.title, "passed": ch.passed,
                        "details": ch.details} for ch in result.checks]}


def write_report(result) -> dict:
    directory = Path(result.directory)
    spec = result.spec
    images = {}
    for study in spec.studies:
        expected = None
        for ch in study.checks:
            if ch.get("kind") == "stable-interval":
                expected = ch.get("expected")
        try:
            img = plot_study(study, [c for c in result.cases if c.study == study.name], result.records,
                             directory / f"{study.name}.png", expected)
        except OutputError:
            raise
        except Exception as exc:  # a plot must not take the report down
            img = None
            print(f"warning: plot of study {study.name} failed: {exc}", file=sys.stderr)
        if img:
            images[study.name] = img.name
    c = result.counts
    verdict = "PASS" if result.passed else "FAIL"
    s = spec.settings
    retried = getattr(result, "retried", 0)
    intro = (f"{c['cases']} cases ({result.ran} run now, {result.resumed} from an earlier run"
             f"{f', {retried} failed ones run again' if retried else ''}) in "
             f"{result.seconds:.1f} s. Agreement: {c['agree']} agree, {c['disagree']} disagree, "
             f"{c['marginal']} marginal (excluded), {c['failed']} failed.")
    if getattr(result, "sample", ""):
        intro += f" A sample: {result.sample}; the checks see only these cases."
    method = (f"Prediction: closed-loop eigenvalues of the analytic linear models (exact delays as Pade "
              f"approximations; the master's sample-and-hold and Jacobi lags modelled), 'marginal' when "
              f"|max Re| < margin (default {s['margin']:g} 1/s). Observation: the largest growth rate of the "
              f"modes identified in the observed signal (matrix pencil fit; for signals that are not a sum "
              f"of damped oscillations, the envelope of |x| in the last third vs the middle third of the "
              f"run), inconclusive when below {s['observed_margin']:g} 1/s (re-run {s['extend']:g}x longer), "
              f"'fell' beyond the fall limit.")
    # markdown
    md = [f"# Co-simulation matrix: {spec.name}", "", spec.description, "",
          f"**{verdict}** — {intro}", "", method, "", "## Checks", "",
          "| study | check | result | details |", "|---|---|---|---|"]
    for ch in sorted(result.checks, key=lambda ch: ch.passed):
        md.append(f"| {ch.study} | {ch.title} | {'pass' if ch.passed else '**FAIL**'} | {ch.details} |")
    for study in spec.studies:
        recs = [r for r in result.records if r["study"] == study.name]
        md += ["", f"## {study.name}: {study.title}", ""]
        if study.claim:
            md += [f"Claim: {study.claim}", ""]
        if study.description:
            md += [study.description.strip(), ""]
        if study.name in images:
            md += [f"![{study.name}]({images[study.name]})", ""]
        md.append("| " + " | ".join(t for _, t in COLUMNS) + " |")
        md.append("|" + "---|" * len(COLUMNS))
        for rec in _sorted(recs):
            row = _row(rec)
            md.append("| " + " | ".join(str(row[k]).replace("|", "\\|") for k, _ in COLUMNS) + " |")
    write_text(directory / "report.md", "\n".join(md) + "\n", "report")
    # html
    e = html.escape
    css = ("body{font-family:sans-serif;margin:2em;max-width:1200px} table{border-collapse:collapse;font-size:12px}"
           "td,th{border:1px solid #ccc;padding:2px 6px} th{background:#eee} .pass{color:#2a7d3f;font-weight:bold}"
           ".fail{color:#c0392b;font-weight:bold} tr.disagree{background:#f8d7da} tr.failed{background:#f5c6cb}"
           "tr.marginal{background:#eeeeee} img{max-width:100%}")
    h = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{e(spec.name)}</title><style>{css}</style></head><body>",
         f"<h1>Co-simulation matrix: {e(spec.name)}</h1>", f"<p>{e(spec.description)}</p>",
         f"<p class='{'pass' if result.passed else 'fail'}'>{verdict}</p><p>{e(intro)}</p><p>{e(method)}</p>",
         "<h2>Checks</h2><table><tr><th>study</th><th>check</th><th>result</th><th>details</th></tr>"]
    for ch in sorted(result.checks, key=lambda ch: ch.passed):
        cls = "pass" if ch.passed else "fail"
        h.append(f"<tr><td>{e(ch.study)}</td><td>{e(ch.title)}</td><td class='{cls}'>{cls}</td><td>{e(ch.details)}</td></tr>")
    h.append("</table>")
    for study in spec.studies:
        recs = [r for r in result.records if r["study"] == study.name]
        h.append(f"<h2>{e(study.name)}: {e(study.title)}</h2>")
        if study.claim:
            h.append(f"<p><b>Claim:</b> {e(study.claim)}</p>")
        if study.description:
            h.append(f"<p>{e(study.description.strip())}</p>")
        if study.name in images:
            h.append(f"<img src='{e(images[study.name])}' alt='{e(study.name)}'>")
        h.append("<table><tr>" + "".join(f"<th>{e(t)}</th>" for _, t in COLUMNS) + "</tr>")
        for rec in _sorted(recs):
            row = _row(rec)
            h.append(f"<tr class='{e(row['agreement'])}'>" + "".join(f"<td>{e(str(row[k]))}</td>" for k, _ in COLUMNS)
                     + "</tr>")
        h.append("</table>")
    h.append("</body></html>")
    write_text(directory / "report.html", "\n".join(h) + "\n", "report")
    summary = _summary(result)
    write_text(directory / "summary.json", json.dumps(summary, indent=2) + "\n", "summary")
    return {"markdown": str(directory / "report.md"), "html": str(directory / "report.html"),
            "images": [str(directory / p) for p in images.values()], "summary": str(directory / "summary.json")}
