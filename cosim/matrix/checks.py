"""Study-level checks of a matrix: the claims, evaluated on predictions and observations.

``[[study.checks]]`` kinds:

``stable-interval``
    ``axis``, ``expected = [lo, hi]``, ``tolerance`` (absolute, in the axis unit). Passes when the
    predicted stability boundaries along the axis (sign changes of max Re between cases, refined
    by Brent's method on the analytic model) are lo and hi within the tolerance, and every case
    whose prediction is decisive is observed stable inside [lo, hi] and unstable outside.
``region``
    ``where`` (an expression of the case variables), ``expect`` = ``stable`` | ``unstable`` |
    ``not-stable`` | ``marginal``. Every case where ``where`` holds must be predicted (beyond the
    margin) and observed so; ``not-stable`` accepts marginal and unstable. At least one case must
    match.
``growth-rate``
    ``expected`` (expression; ``max_re`` is the prediction), ``rtol``, ``atol`` [1/s], ``where``:
    the observed growth rate (fitted envelope slope) equals the expected value.
``agreement``
    (implicit for every study) no case disagrees with its prediction and none failed.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from cosim.matrix import expr
from cosim.matrix.classify import UNSTABLE
from cosim.matrix.predict import max_re_at


@dataclass
class CheckResult:
    study: str
    kind: str
    title: str
    passed: bool
    details: str
    data: dict = field(default_factory=dict)


def _scope(case, record) -> dict:
    scope = dict(case.variables)
    pred = record.get("prediction") or {}
    obs = record.get("observed") or {}
    scope["max_re"] = pred.get("max_re", math.nan) if pred.get("max_re") is not None else math.nan
    scope["growth_rate"] = obs.get("growth_rate") if obs.get("growth_rate") is not None else math.nan
    for k, v in (pred.get("tuned") or {}).items():
        scope[k.replace(".", "_")] = v
    return scope


def _matching(study, pairs, where: str | None):
    if not where:
        return list(pairs)
    out = []
    for case, rec in pairs:
        if expr.evaluate(where, _scope(case, rec)):
            out.append((case, rec))
    return out


def _agreement(study, pairs) -> CheckResult:
    bad = [r for _, r in pairs if r.get("agreement") == "disagree"]
    failed = [r for _, r in pairs if r.get("agreement") == "failed"]
    marginal = sum(1 for _, r in pairs if r.get("agreement") == "marginal")
    agree = sum(1 for _, r in pairs if r.get("agreement") == "agree")
    details = f"{agree} agree, {len(bad)} disagree, {marginal} marginal (excluded), {len(failed)} failed"
    if bad:
        details += "; disagreeing: " + ", ".join(r["label"] for r in bad[:8]) + (" ..." if len(bad) > 8 else "")
    if failed:
        details += "; failed: " + ", ".join(r["label"] for r in failed[:8]) + (" ..." if len(failed) > 8 else "")
    return CheckResult(study.name, "agreement", "co-simulation agrees with the analytic prediction",
                       not bad and not failed, details)


def _stable_interval(study, pairs, check, fmu_paths) -> CheckResult:
    from scipy.optimize import brentq

    axis = check["axis"]
    lo, hi = (float(v) for v in check["expected"])
    tol = float(check.get("tolerance", 1e-3))
    title = check.get("title", f"stable exactly for {lo:g} < {axis} < {hi:g} (tolerance {tol:g})")
    points = sorted(((case.values[axis], case, rec) for case, rec in pairs
                     if axis in case.values and rec.get("prediction")), key=lambda p: p[0])
    if len(points) < 2:
        return CheckResult(study.name, "stable-interval", title, False, f"fewer than 2 predicted cases along '{axis}'")
    others = {k: v for k, v in points[0][1].values.items() if k != axis}

    def f(x):
        return max_re_at(study, {**others, axis: x}, fmu_paths)

    bounds = []
    for (x0, _, r0), (x1, _, r1) in zip(points, points[1:]):
        a, b = r0["prediction"]["max_re"], r1["prediction"]["max_re"]
        if (a < 0) != (b < 0):
            root = brentq(f, x0, x1, xtol=1e-10, rtol=1e-12)
            bounds.append((root, "enters" if b < 0 else "leaves"))
    predicted = None
    if len(bounds) == 2 and bounds[0][1] == "enters" and bounds[1][1] == "leaves":
        predicted = (bounds[0][0], bounds[1][0])
    problems = []
    if predicted is None:
        problems.append(f"predicted boundaries {[round(b, 6) for b, _ in bounds]} are not one stable interval")
    else:
        if abs(predicted[0] - lo) > tol or abs(predicted[1] - hi) > tol:
            problems.append(f"predicted interval {predicted[0]:.6g}-{predicted[1]:.6g} differs from "
                            f"{lo:g}-{hi:g} by more than {tol:g}")
    wrong = []
    lower = [None, None]  # last observed unstable below lo, first observed stable above lo
    upper = [None, None]  # last observed stable below hi, first observed unstable above hi
    for x, case, rec in points:
        obs = (rec.get("observed") or {}).get("class")
        pclass = rec["prediction"]["class"]
        inside = lo < x < hi
        if obs == "stable":
            if x >= lo and (lower[1] is None or x < lower[1]):
                lower[1] = x
            if x <= hi and (upper[0] is None or x > upper[0]):
                upper[0] = x
        if obs in UNSTABLE:
            if x <= lo and (lower[0] is None or x > lower[0]):
                lower[0] = x
            if x >= hi and (upper[1] is None or x < upper[1]):
                upper[1] = x
        if pclass == "marginal":
            continue
        if (inside and obs != "stable") or (not inside and obs not in UNSTABLE):
            wrong.append(f"{case.label}: observed {obs}")
    if wrong:
        problems.append("observations contradict the interval: " + "; ".join(wrong[:6]))
    fmt = lambda v: "-" if v is None else f"{v:g}"  # noqa: E731
    observed = (f"observed: unstable at {fmt(lower[0])}, stable from {fmt(lower[1])} ... stable to {fmt(upper[0])}, "
                f"unstable at {fmt(upper[1])}")
    pred_text = f"predicted {predicted[0]:.6g}-{predicted[1]:.6g}" if predicted else "no predicted interval"
    details = f"{pred_text}; {observed}" + ("; " + "; ".join(problems) if problems else "")
    return CheckResult(study.name, "stable-interval", title, not problems, details,
                       {"predicted": predicted, "expected": [lo, hi], "observed_lower": lower, "observed_upper": upper})


def _region(study, pairs, check) -> CheckResult:
    where = check.get("where", "True")
    expect = check["expect"]
    if expect not in ("stable", "unstable", "not-stable", "marginal"):
        raise ValueError(f"study '{study.name}': region check: expect must be stable, unstable, not-stable "
                         "or marginal")
    title = check.get("title", f"{expect} where {where}")
    matched = _matching(study, pairs, where)
    if not matched:
        return CheckResult(study.name, "region", title, False, f"no case matches '{where}'")
    wrong = []
    for case, rec in matched:
        pred = (rec.get("prediction") or {}).get("class")
        obs = (rec.get("observed") or {}).get("class")
        if expect == "stable":
            ok = pred == "stable" and obs == "stable"
        elif expect == "unstable":
            ok = pred == "unstable" and obs in UNSTABLE
        elif expect == "marginal":
            ok = pred == "marginal" and obs == "marginal"
        else:
            ok = pred != "stable" and obs != "stable" and obs is not None
        if not study.settings["predict"]:
            ok = (obs == "stable") if expect == "stable" else (obs in UNSTABLE if expect == "unstable" else obs != "stable")
        if not ok:
            wrong.append(f"{case.label}: predicted {pred}, observed {obs}")
    details = f"{len(matched) - len(wrong)}/{len(matched)} cases as expected"
    if wrong:
        details += "; " + "; ".join(wrong[:6]) + (" ..." if len(wrong) > 6 else "")
    return CheckResult(study.name, "region", title, not wrong, details)


def _growth_rate(study, pairs, check) -> CheckResult:
    expected = check.get("expected", "max_re")
    rtol, atol = float(check.get("rtol", 0.02)), float(check.get("atol", 0.0))
    where = check.get("where")
    title = check.get("title", f"observed growth rate = {expected} (rtol {rtol:g}, atol {atol:g} 1/s)")
    matched = _matching(study, pairs, where)
    if not matched:
        return CheckResult(study.name, "growth-rate", title, False, f"no case matches '{where}'")
    wrong, worst = [], 0.0
    for case, rec in matched:
        scope = _scope(case, rec)
        want = float(expr.evaluate(expected, scope))
        got = scope["growth_rate"]
        if got is None or not math.isfinite(got):
            wrong.append(f"{case.label}: no growth rate observed")
            continue
        err = abs(got - want)
        worst = max(worst, err / abs(want) if want else err)
        if err > atol + rtol * abs(want):
            wrong.append(f"{case.label}: observed {got:.5g}, expected {want:.5g} 1/s")
    details = f"{len(matched) - len(wrong)}/{len(matched)} within tolerance; largest relative error {worst:.2g}"
    if wrong:
        details += "; " + "; ".join(wrong[:6])
    return CheckResult(study.name, "growth-rate", title, not wrong, details)


def evaluate(spec, cases, records, fmu_paths) -> list[CheckResult]:
    by_key = {r["key"]: r for r in records}
    results = []
    for study in spec.studies:
        pairs = [(c, by_key[c.key]) for c in cases if c.study == study.name and c.key in by_key]
        results.append(_agreement(study, pairs))
        for check in study.checks:
            kind = check["kind"]
            try:
                if kind == "agreement":
                    continue
                if kind == "stable-interval":
                    results.append(_stable_interval(study, pairs, check, fmu_paths))
                elif kind == "region":
                    results.append(_region(study, pairs, check))
                elif kind == "growth-rate":
                    results.append(_growth_rate(study, pairs, check))
            except Exception as exc:
                results.append(CheckResult(study.name, kind, check.get("title", kind), False,
                                           f"check could not be evaluated: {type(exc).__name__}: {exc}"))
    return results
