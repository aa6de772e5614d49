"""Run the minimal models of docs/pymoca-upstream.md against pymoca alone and write that file.

Each case is a bug (or a missing feature) of pymoca that cosim/compiler/pymoca_patches.py works
around. This script never imports cosim, so pymoca runs unpatched: the "Actual" section of each
report is what it prints here. Run it from the repository root after a change of the pymoca pin::

    python docs/pymoca_upstream.py            # rewrite docs/pymoca-upstream.md
    python docs/pymoca_upstream.py --check    # exit 1 if the file differs from a fresh run
    python docs/pymoca_upstream.py --stdout   # print it
"""
from __future__ import annotations

import argparse
import contextlib
import io
import textwrap
from dataclasses import dataclass
from importlib.metadata import version
from pathlib import Path

DOCUMENT = Path(__file__).with_name("pymoca-upstream.md")


@dataclass(frozen=True)
class Case:
    """One upstream report: an anchor (linked from the patch), the patch, the model and what the
    Modelica specification (or a tool) gives."""

    anchor: str
    title: str
    patch: str  # the function(s) of cosim/compiler/pymoca_patches.py that work around it
    model: str  # the class to flatten
    text: str  # Modelica source
    expected: str
    show: tuple[str, ...] = ()  # flat symbols whose value/fixed attributes are printed
    feature: bool = False  # a missing feature rather than a wrong result


CASES = [
    Case("name-capture", "A modifier's right-hand name is captured by the component",
         "_mark_flat, _skip_marked", "NameCapture", """
model NameCapture
  model Frame
    parameter Real m = 1;
    Real x;
  equation
    x = m;
  end Frame;
  parameter Real m = 2;
  Frame frame(m = m);
end NameCapture;
""", "The right-hand `m` of `frame(m = m)` is the enclosing model's `m` (MLS 7.2.4): the binding "
         "is `frame.m = m`, so `frame.x = 2`.", show=("frame.m",)),
    Case("function-names", "A Modelica function's CasADi name is its dotted class name",
         "_named_functions", "P.M", """
package P
  function f
    input Real u;
    output Real y;
  algorithm
    y := 2*u;
  end f;
  model M
    Real y;
  equation
    y = P.f(time);
  end M;
end P;
""", "The model translates; the CasADi function gets a valid identifier (e.g. `P_f`)."),
    Case("fixed-given", "The flat model does not tell a given `fixed` from the default",
         "_mark_fixed, _carry_fixed", "Fixed", """
model Fixed
  Real x(start = 1);
  Real y(start = 1, fixed = false);
equation
  der(x) = -x;
  der(y) = -y;
end Fixed;
""", "A way to tell `x` (no `fixed` given: a tool may take the start value as the initial value) "
         "from `y` (`fixed = false` written: the start value is a guess), e.g. an attribute that is "
         "`None` unless it was given.", show=("x", "y"), feature=True),
    Case("short-connectors", "Short connector classes `connector RealInput = input Real`",
         "_keep_base_prefix, _scalar_connectors", "Short.Chain", """
package Short
  connector RealInput = input Real;
  connector RealOutput = output Real;
  block Gain
    RealInput u;
    RealOutput y;
  equation
    y = 2*u;
  end Gain;
  model Chain
    RealInput u;
    Gain a;
    Gain b;
  equation
    connect(u, a.u);
    connect(a.y, b.u);
  end Chain;
end Short;
""", "`u` is an input; the connections are `u = a.u` and `a.y = b.u` (MLS 9.1: a connector of a "
         "built-in type is that variable), so the model has the variables u, a.u, a.y, b.u, b.y."),
    Case("derived-type-constants", "The value of a constant of a derived type is not found",
         "_value_argument, _constant_values", "Data.M", """
package Data
  type Length = Real(unit = "m");
  constant Length w = 1.5;
  model M
    parameter Real p = Data.w;
  end M;
end Data;
""", "`p = 1.5`, as with `constant Real w = 1.5`.", show=("p",)),
    Case("constants-in-equations", "Package constants in equations are not resolved",
         "_package_constants_in_equations", "Consts.M", """
package Consts
  constant Real g = 9.81;
  model M
    Real v(start = 0, fixed = true);
  equation
    der(v) = Consts.g;
  end M;
end Consts;
""", "`der(v) = 9.81` (MLS 5.6.2: the constant is evaluated)."),
    Case("modified-constants", "Modified constants from the second level down have their default value",
         "_constant_values", "Nest.Sys", """
package Nest
  model J
    constant Integer n = 2;
    Real x[n];
  equation
    x = fill(1, n);
  end J;
  model B
    constant Integer n = 2;
    J j(n = n);
  end B;
  model Sys
    B b(n = 3);
  end Sys;
end Nest;
""", "MLS 7.2: `b.n = 3` and `b.j.n = b.n = 3`, so `b.j.x` has 3 elements."),
    Case("inherited-constants", "A constant given by a modifier of `extends` in a package has no value",
         "_inherited_constants", "Sets.M", """
package Sets
  partial package PartialSet
    constant Real w;
  end PartialSet;
  package A
    extends PartialSet(w = 1.5);
  end A;
  model M
    parameter Real p = A.w;
  end M;
end Sets;
""", "`p = 1.5`.", show=("p",)),
    Case("record-bindings", "Record bindings are ignored", "_record_bindings", "Rec.Bound", """
package Rec
  record Body
    parameter Real m = 1;
  end Body;
  model Mass
    parameter Body b;
    Real y;
  equation
    y = b.m;
  end Mass;
  model Bound
    parameter Body rb(m = 3);
    Mass body(b = rb);
  end Bound;
end Rec;
""", "`body.b.m = rb.m` (3), so `body.y = 3`; or an error if the binding is not supported.",
         show=("body.b.m",)),
    Case("component-redeclare", "A redeclared component keeps the equations of the replaced class",
         "_replacing_redeclares", "Wh.Use", """
package Wh
  partial model PartialWheel
    Real y;
  end PartialWheel;
  model Knife
    extends PartialWheel;
  equation
    y = 1;
  end Knife;
  model Torus
    extends PartialWheel;
  equation
    y = 2;
  end Torus;
  model Bike
    replaceable Knife w constrainedby PartialWheel;
  end Bike;
  model Use
    Bike bike(redeclare Torus w);
  end Use;
end Wh;
""", "MLS 7.3: the component's class is `Torus` alone: one equation, `bike.w.y = 2`."),
    Case("two-redeclares", "The second of two redeclared components of one class gets both classes",
         "_replacing_redeclares", "Wh2.ExtendedTwo", """
package Wh2
  partial model PartialWheel
    Real y;
  end PartialWheel;
  model Knife
    extends PartialWheel;
  equation
    y = 1;
  end Knife;
  model Torus
    extends PartialWheel;
    parameter Real rc = 0.1;
  equation
    y = 2 + rc;
  end Torus;
  model Two
    replaceable Knife a constrainedby PartialWheel;
    replaceable Knife b constrainedby PartialWheel;
  end Two;
  model ExtendedTwo
    extends Two(redeclare Torus a, redeclare Torus b(rc = 0.2));
  end ExtendedTwo;
end Wh2;
""", "Two equations: `a.y = 2 + a.rc` and `b.y = 2 + b.rc`, with `a.rc = 0.1`, `b.rc = 0.2`."),
    Case("constraining-clause", "The modifiers of a constraining clause are dropped",
         "_keep_constraining_clause, _replacing_redeclares", "Cc.Use", """
package Cc
  partial model PartialWheel
    parameter Real r = 0.3;
    Real y;
  equation
    y = r;
  end PartialWheel;
  model Knife
    extends PartialWheel;
  end Knife;
  model Bike
    replaceable Knife w constrainedby PartialWheel(r = 0.5);
  end Bike;
  model Use
    Bike bike;
  end Use;
end Cc;
""", "MLS 7.3.2: the modifiers of the constraining clause apply to the default: `bike.w.r = 0.5`.",
         show=("bike.w.r",)),
    Case("array-constructors", "An array constructor with a symbolic element fails in the CasADi backend",
         "_casadi_arrays", "Arr", """
model Arr
  parameter Real m = 2;
  Real x[2](each start = 1, each fixed = true);
equation
  der(x) = {1, m*x[1]};
end Arr;
""", "`der(x[1]) = 1`, `der(x[2]) = m*x[1]`."),
    Case("dense-identity", "`identity(n)` is a sparse CasADi matrix", "_casadi_arrays", "Ident", """
model Ident
  parameter Real k = 2;
  parameter Real K[2, 2] = -k*identity(2);
  Real x[2](each start = 1, each fixed = true);
equation
  der(x) = K*x;
end Ident;
""", "The value of `K` is a dense 2x2 matrix, as `{{-k, 0}, {0, -k}}` and the declaration `K[2, 2]` are "
         "(CasADi refuses a sparse value where it must match a dense symbol: \"Sparsities of v and vdef "
         "must match\", seen in cosim's later steps, not in pymoca's own).", feature=True),
    Case("derived-type-arrays", "An array component of a derived type loses its dimensions",
         "_leaf_dimensions (cosim/compiler/pymoca_flattening.py)", "Leaf.M", """
package Leaf
  type Length = Real(unit = "m");
  connector C
    Length p[3];
    flow Real f[3];
  end C;
  model M
    C c;
  equation
    c.p[2] = 1;
    c.p[1] = 0;
    c.p[3] = 0;
  end M;
end Leaf;
""", "`c.p` is an array of 3 elements."),
]


def _value(attribute) -> str:
    value = getattr(attribute, "value", attribute)
    return repr(value)


def _casadi_value(value) -> str:
    """A value of the CasADi model; a matrix with its structural nonzeros (a sparse one has fewer)."""
    if hasattr(value, "nnz") and hasattr(value, "numel") and value.numel() > 1:
        return f"{value} ({value.nnz()} of {value.numel()} elements structurally nonzero)"
    return str(value)


def _run(case: Case) -> str:
    """What pymoca (unpatched) makes of ``case``: its flat model in CasADi form, or its error."""
    from pymoca import ast, parser, tree
    from pymoca.backends.casadi._options import _merge_default_options
    from pymoca.backends.casadi.generator import Generator, GeneratorWalker

    lines = []
    try:
        root = parser.parse(case.text)
        flat = tree.flatten(root, ast.ComponentRef.from_string(case.model))
        symbols = flat.classes[case.model].symbols
        for name in case.show:
            symbol = symbols.get(name)
            if symbol is None:
                lines.append(f"flat symbol {name}: (none)")
            else:
                lines.append(f"flat symbol {name}: value={_value(symbol.value)} fixed={_value(symbol.fixed)}")
        generator = Generator(flat, case.model, _merge_default_options({}))
        with contextlib.redirect_stdout(io.StringIO()):
            GeneratorWalker().walk(generator, flat)
    except Exception as exc:  # the error is the report's actual result
        message = str(exc).strip().splitlines()
        lines.append(f"{type(exc).__name__}: {message[0] if message else ''}")
        return "\n".join(lines)
    model = generator.model
    for group in ("states", "alg_states", "inputs", "outputs", "constants", "parameters"):
        variables = getattr(model, group)
        if variables:
            described = ", ".join(f"{v.symbol.name()}{list(v.symbol.shape)}" + (
                f"={_casadi_value(v.value)}" if group in ("constants", "parameters") else "") for v in variables)
            lines.append(f"{group}: {described}")
    lines.append(f"equations: {[str(e) for e in model.equations]}")
    return "\n".join(lines)


def document() -> str:
    """The Markdown text of docs/pymoca-upstream.md from fresh runs of every case."""
    pymoca, casadi = version("pymoca"), version("casadi")
    parts = [
        "# pymoca: reports ready to send upstream\n",
        f"cosim pins pymoca {pymoca} (pyproject.toml) and works around the bugs below in "
        "`cosim/compiler/pymoca_patches.py` (and `cosim/compiler/pymoca_flattening.py`); each patch "
        "links its report here. Every \"Actual\" block is the output of `python docs/pymoca_upstream.py`, "
        "which runs the model with pymoca alone (parse, `pymoca.tree.flatten`, the CasADi generator), "
        "never with cosim's patches. When a release fixes a case, its patch can go and the pin move.\n",
        f"Versions: pymoca {pymoca}, CasADi {casadi}.\n",
        "Reproduce one case (`MODEL.mo` holding the model):\n",
        "```python\nfrom pymoca import ast, parser, tree\n"
        "from pymoca.backends.casadi._options import _merge_default_options\n"
        "from pymoca.backends.casadi.generator import Generator, GeneratorWalker\n\n"
        "flat = tree.flatten(parser.parse(open('MODEL.mo').read()), ast.ComponentRef.from_string('NAME'))\n"
        "generator = Generator(flat, 'NAME', _merge_default_options({}))\n"
        "GeneratorWalker().walk(generator, flat)\nprint(generator.model)\n```\n",
        "## Contents\n",
        "\n".join(f"- [{case.title}](#{case.anchor})" for case in CASES) + "\n",
    ]
    for case in CASES:
        kind = "Missing feature" if case.feature else "Bug"
        parts += [
            f'<a id="{case.anchor}"></a>\n\n## {case.title}\n',
            f"{kind}; pymoca {pymoca}. Worked around in cosim by `{case.patch}`.\n",
            f"Model (flatten `{case.model}`):\n",
            f"```modelica\n{textwrap.dedent(case.text).strip()}\n```\n",
            f"Expected: {case.expected}\n",
            f"Actual (pymoca {pymoca}):\n",
            f"```\n{_run(case)}\n```\n",
        ]
    return "\n".join(parts)


def main(argv=None) -> int:
    arguments = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    arguments.add_argument("--check", action="store_true", help="compare with the file instead of writing it")
    arguments.add_argument("--stdout", action="store_true", help="print the document instead of writing it")
    options = arguments.parse_args(argv)
    text = document()
    if options.stdout:
        print(text, end="")
        return 0
    if options.check:
        same = DOCUMENT.exists() and DOCUMENT.read_text(encoding="utf-8") == text
        print(f"{DOCUMENT.name}: {'up to date' if same else 'differs from a fresh run'}")
        return 0 if same else 1
    DOCUMENT.write_text(text, encoding="utf-8")
    print(f"wrote {DOCUMENT}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
