"""Every command and code block of README.md and of the User's Guide (``modelica/Bicycle/UsersGuide/*.mo``,
the HTML of their Documentation annotations) runs as printed.

The blocks are extracted from the files when the tests are collected, so a changed README is tested as it
reads:

- a fenced block without a language (or ``sh``, ``shell``, ``bash``, ``console``): lines starting with
  ``$ `` are commands and the lines after each its output, which must appear in order in what the
  command prints, numbers aside (a line ``...`` stands for lines left out); a block without ``$ `` holds
  one command per line;
- inline code (Markdown backticks, HTML ``<code>``) that starts with ``cosim ``, ``pip ``, ``pytest`` or
  ``python ``;
- a ``python`` block is executed; a ``modelica`` block (in the guide: a ``<pre>`` block) is flattened and
  made explicit by the project's compiler (every check of a build before code generation), and written to
  the file the text names after its class (``variants/NAME.mo``) for the commands after it; a ``toml``
  block is loaded as what the paragraph before it says it is (a system file, a parameter set, a matrix
  spec) and written to the file that paragraph names (``saved as `push.toml```).

The steps of one document run in document order in one working folder (a temporary folder in which the
project's ``cosim`` and ``modelica`` folders are linked, so that "in this folder" holds and every result
stays in the temporary folder), with the session's FMU folder (COSIM_FMU_DIR, built once by the ``fmus``
fixture). A command must exit with status 0, and must be complete: placeholders (``...``, a word in
capitals such as MODEL, ``[``, ``|``) are allowed only in a form marked as a synopsis (a ``synopsis``
block, or the word "synopsis" right before the inline code), which is not run.

The README's two set-up commands, ``pip install -e '.[test]' && cosim demo`` and ``pytest``, are not run
here (pip would reinstall the project under test, pytest would run this suite inside itself): the tests
assert that they are printed exactly so in the set-up section, that no other pip or pytest command is
printed, and that ``.ci/run`` runs the same two commands on a clean clone, which is what proves them.
"""
from __future__ import annotations

import html
import os
import re
import shlex
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT, variant_library

# the quick run (-m 'not slow') leaves this module out: it runs the command line in fresh processes
pytestmark = pytest.mark.slow

README = ROOT / "README.md"
GUIDE = ROOT / "modelica" / "Bicycle" / "UsersGuide"
DOCUMENTS = [README] + sorted(GUIDE.glob("*.mo"))
SETUP_COMMANDS = ["pip install -e '.[test]' && cosim demo", "pytest"]
PROGRAMS = ("cosim", "python", "pip", "pytest")
SHELL_LANGUAGES = ("", "sh", "shell", "bash", "console")
#: Fenced blocks that are not code: output shown on its own, synopses (placeholders allowed).
NOT_RUN_LANGUAGES = ("text", "synopsis")
#: Commands that fail today for a known reason being fixed elsewhere: strict, so that they turn green
#: (and the mark must go) once it is.
KNOWN_FAILURES: dict[str, str] = {}
COMMAND_TIMEOUT = 600  # s: a hung command fails its test instead of the suite


# -- extraction ---------------------------------------------------------------------------------

@dataclass
class Step:
    """One thing a document shows that the tests run, at ``line`` of ``document``."""

    document: str
    line: int
    kind: str  # "command", "python", "modelica", "toml"
    text: str
    output: list[str] | None = None  # for "$ " commands: the output shown after them
    synopsis: bool = False  # marked as a synopsis: not run
    context: str = ""  # the paragraph before a block
    files: list[str] = field(default_factory=list)  # file names the document gives (for blocks)

    @property
    def id(self) -> str:
        return f"{self.document}:{self.line}:{self.text.splitlines()[0][:70]}"


def is_command(text: str) -> bool:
    return text.split(" ", 1)[0] in PROGRAMS and (text in ("pytest",) or " " in text)


def placeholders(command: str) -> list[str]:
    """The parts of ``command`` that stand for something else: ``...``, ``[``, ``]``, ``|`` (outside
    quotes) and words in capitals (MODEL, FILE, DIR, SET)."""
    found = ["..."] if "..." in command else []
    try:
        words = shlex.split(command, posix=False)  # quotes kept: brackets inside quotes are no syntax
    except ValueError:
        return found + ["unbalanced quotes"]
    for word in words:
        if word[:1] in "'\"":
            continue
        found += [c for c in "[]|" if c in word]
        found += re.findall(r"(?<![\w.-])[A-Z][A-Z_]+(?!\w)", word)
    return found


def _paragraph_before(lines: list[str], index: int) -> str:
    """The paragraph before ``lines[index]`` (blank lines between them skipped)."""
    end = index
    while end > 0 and not lines[end - 1].strip():
        end -= 1
    start = end
    while start > 0 and lines[start - 1].strip():
        start -= 1
    return " ".join(lines[start:end])


def markdown_steps(text: str, document: str) -> list[Step]:
    """The steps of a Markdown text, in document order."""
    steps: list[Step] = []
    lines = text.split("\n")
    i = 0
    while i < len(lines):
        fence = re.match(r"^\s*```(\S*)\s*$", lines[i])
        if fence:
            language, start = fence.group(1), i
            i += 1
            body = []
            while i < len(lines) and not re.match(r"^\s*```\s*$", lines[i]):
                body.append(lines[i])
                i += 1
            i += 1
            context = _paragraph_before(lines, start)
            steps += _block_steps(language, body, document, start + 2, context)
            continue
        for match in re.finditer(r"`([^`]+)`", lines[i]):
            span = match.group(1).replace("\\|", "|").strip()
            if is_command(span):
                before = lines[i][:match.start()]
                steps.append(Step(document, i + 1, "command", span,
                                  synopsis=bool(re.search(r"\bsynopsis\b\W*$", before, re.I))))
        i += 1
    return steps


def _block_steps(language: str, body: list[str], document: str, line: int, context: str) -> list[Step]:
    language = language.lower()
    if language in NOT_RUN_LANGUAGES:
        return []
    if language in ("python", "modelica", "toml"):
        files = [f for f in re.findall(r"`([^`\s]+\.(?:toml|mo))`", context)]
        return [Step(document, line, language, "\n".join(body), context=context, files=files)]
    if language not in SHELL_LANGUAGES:
        raise ValueError(f"{document}:{line - 1}: a ```{language} block: no test knows how to run it (use python, "
                         f"modelica, toml, a shell block, or {', '.join(NOT_RUN_LANGUAGES)} for what is not run)")
    steps = []
    if any(row.startswith("$ ") for row in body):
        for k, row in enumerate(body):
            if row.startswith("$ "):
                steps.append(Step(document, line + k, "command", row[2:].strip(), output=[]))
            elif steps:
                steps[-1].output.append(row)
            elif row.strip():
                raise ValueError(f"{document}:{line + k}: output before the first '$ ' command")
        return steps
    for k, row in enumerate(body):
        if not row.strip() or row.lstrip().startswith("#"):
            continue
        if not is_command(row.strip()):
            raise ValueError(f"{document}:{line + k}: '{row.strip()}' in a shell block is no command of "
                             f"{', '.join(PROGRAMS)} (mark shown output with '$ ' commands, or use ```text)")
        steps.append(Step(document, line + k, "command", row.strip()))
    return steps


def guide_steps(text: str, document: str) -> list[Step]:
    """The steps of a User's Guide class: ``<pre>`` blocks (Modelica classes) and ``<code>`` commands of its
    Documentation HTML, in document order; the files the text names (``<code>DIR/NAME.mo</code>``) go with
    the block that defines NAME."""
    def line_of(offset: int) -> int:
        return text.count("\n", 0, offset) + 1

    def clean(fragment: str) -> str:
        return html.unescape(re.sub(r"<[^>]+>", "", fragment.replace('\\"', '"')))

    named = [clean(m.group(1)).strip() for m in re.finditer(r"<code>(.*?)</code>", text, re.S)]
    files = [f for f in named if re.fullmatch(r"[\w./-]+\.mo", f)]
    found = []
    for match in re.finditer(r"<pre>(.*?)</pre>|<code>(.*?)</code>", text, re.S):
        if match.group(1) is not None:
            body = clean(match.group(1)).strip("\n")
            name = re.match(r"\s*(?:\w+\s+)*?(?:model|block|class|package|connector|record)\s+(\w+)", body)
            if not name:
                raise ValueError(f"{document}:{line_of(match.start())}: a <pre> block that is no Modelica class")
            found.append(Step(document, line_of(match.start()) + 1, "modelica", body,
                              files=[f for f in files if Path(f).stem == name.group(1)]))
        else:
            span = re.sub(r"\s+", " ", clean(match.group(2))).strip()
            if is_command(span):
                before = text[max(0, match.start() - 30):match.start()]
                found.append(Step(document, line_of(match.start()), "command", span,
                                  synopsis=bool(re.search(r"\bsynopsis\b\W*$", before, re.I))))
    return found


def document_steps(path: Path) -> list[Step]:
    name = str(path.relative_to(ROOT))
    text = path.read_text(encoding="utf-8")
    return markdown_steps(text, name) if path.suffix == ".md" else guide_steps(text, name)


STEPS = {str(p.relative_to(ROOT)): document_steps(p) for p in DOCUMENTS}
ALL_STEPS = [s for steps in STEPS.values() for s in steps]


def _is_setup(step: Step) -> bool:
    return step.kind == "command" and step.text.split(" ", 1)[0] in ("pip", "pytest")


RUN_STEPS = [s for s in ALL_STEPS if not s.synopsis and not _is_setup(s)]


# -- running ------------------------------------------------------------------------------------

def _normalized(line: str) -> str:
    """A line with its numbers replaced by '#' and its white space collapsed."""
    return " ".join(re.sub(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?", "#", line).split())


def output_matches(shown: list[str], printed: str) -> list[str]:
    """The lines of ``shown`` that do not appear, in order and numbers aside, in ``printed`` (a shown line
    ``...`` stands for lines left out)."""
    actual = [_normalized(line) for line in printed.splitlines()]
    position, missing = 0, []
    for line in shown:
        if not line.strip() or line.strip() == "...":
            continue
        wanted = _normalized(line)
        try:
            position = actual.index(wanted, position) + 1
        except ValueError:
            missing.append(line)
    return missing


def _argv(command: str) -> list[str]:
    words = shlex.split(command)
    if words[0] == "cosim":  # the installed script is `python -m cosim` of this interpreter
        return [sys.executable, "-m", "cosim", *words[1:]]
    if words[0] == "python":
        return [sys.executable, *words[1:]]
    raise AssertionError(f"'{command}': only cosim and python commands are run by the tests")


class DocumentRun:
    """The steps of one document, run in order in one working folder (each step once)."""

    def __init__(self, steps: list[Step], folder: Path):
        self.steps, self.folder = steps, folder
        self.results: dict[int, object] = {}
        self.namespaces: dict[int, dict] = {}
        for name in ("cosim", "modelica"):  # "in this folder": the project's files, read only
            (folder / name).symlink_to(ROOT / name, target_is_directory=True)

    def result(self, step: Step):
        """What running ``step`` gave (an exception is returned, not raised), running every step of the
        document before it first."""
        index = self.steps.index(step)
        for k in range(index + 1):
            if k not in self.results:
                try:
                    self.results[k] = self._run(k, self.steps[k])
                except Exception as exc:  # kept for the step's own test; later steps still run
                    self.results[k] = exc
        return self.results[index]

    def _run(self, k: int, step: Step):
        if step.kind == "command":
            outputs = []
            for part in step.text.split(" && "):
                done = subprocess.run(_argv(part), cwd=self.folder, capture_output=True, text=True,
                                      timeout=COMMAND_TIMEOUT)
                outputs.append(done)
                if done.returncode != 0:
                    break
            return outputs
        if step.kind == "python":
            namespace = {"__name__": "__main__"}
            here = os.getcwd()
            os.chdir(self.folder)
            try:
                exec(compile(step.text, f"{step.document}:{step.line}", "exec"), namespace)
            finally:
                os.chdir(here)
            self.namespaces[k] = namespace
            return namespace
        for name in step.files:
            target = self.folder / name
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_text(step.text + "\n", encoding="utf-8")
        if step.kind == "modelica":
            return _compile_modelica(step, self.folder / f"modelica-check-{k}")
        return _load_toml(step, self.folder / (step.files[0] if step.files else f"block-{k}.toml"))


def _compile_modelica(step: Step, folder: Path):
    from cosim.compiler.flatten import flatten
    from cosim.compiler.ode import make_explicit

    kind, name = re.search(r"(model|block|class|package|connector|record)\s+(\w+)", step.text).groups()
    library = variant_library(folder, {name: step.text}, package="Documented")
    if kind == "package":  # a package of variants: each of its models
        return [make_explicit(flatten(library, f"Documented.{name}.{model}"))
                for model in re.findall(r"^\s+model (\w+)", step.text, re.M)]
    return make_explicit(flatten(library, f"Documented.{name}"))


def _load_toml(step: Step, path: Path):
    if not path.exists():
        path.write_text(step.text + "\n", encoding="utf-8")
    context = step.context.lower()
    if "system file" in context:
        from cosim.cosimulation.system import load_system

        return load_system(path)
    if "parameter set" in context:
        from cosim.analytic.parameters import load_parameter_set

        return load_parameter_set(path)
    if "matrix spec" in context:
        from cosim.matrix import load_spec

        return load_spec(path)
    raise AssertionError(f"{step.document}:{step.line}: the paragraph before the ```toml block does not say "
                         "what it is (a system file, a parameter set, a matrix spec)")


@pytest.fixture(scope="module")
def runs(fmus, tmp_path_factory) -> dict[str, DocumentRun]:
    """One run per document, in its own working folder; every exported model built first (the session's
    COSIM_FMU_DIR, shared with the other tests)."""
    return {document: DocumentRun(steps, tmp_path_factory.mktemp(Path(document).stem))
            for document, steps in STEPS.items()}


def _param(step: Step):
    reason = KNOWN_FAILURES.get(step.text) if step.kind == "command" else None
    marks = [pytest.mark.xfail(strict=True, reason=reason)] if reason else []
    return pytest.param(step, id=step.id, marks=marks)


# -- the tests ----------------------------------------------------------------------------------

@pytest.mark.parametrize("step", [_param(s) for s in RUN_STEPS])
def test_documented_step_runs_as_printed(runs, step):
    if step.kind == "command":
        assert not placeholders(step.text), \
            f"{step.document}:{step.line}: '{step.text}' has placeholders {placeholders(step.text)}: print a " \
            "complete command, or mark the form as a synopsis"
    result = runs[step.document].result(step)
    if isinstance(result, Exception):
        raise result
    if step.kind != "command":
        return
    last = result[-1]
    assert last.returncode == 0, f"{step.text}: exit {last.returncode}\n{last.stdout[-3000:]}\n{last.stderr[-3000:]}"
    if step.output:
        printed = "".join(done.stdout for done in result)
        missing = output_matches(step.output, printed)
        assert not missing, f"{step.text}: the shown lines {missing} are not in its output:\n{printed[-3000:]}"


def test_setup_commands_are_the_two_ci_runs():
    """The README's set-up section prints exactly the two commands; they are the only pip and pytest
    commands of the documents, and .ci/run (CI, on a clean clone) runs them."""
    setup = [s for s in ALL_STEPS if _is_setup(s)]
    assert [s.text for s in setup] == SETUP_COMMANDS
    assert {s.document for s in setup} == {"README.md"}
    text = README.read_text(encoding="utf-8")
    section = text[text.index("\n## Set-up"):]
    section = section[:section.index("\n## ", 1)]
    for command in SETUP_COMMANDS:
        assert f"\n```\n{command}\n```\n" in section, command
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    assert any(line.endswith("-e '.[test]' && cosim demo") and "pip install" in line for line in ci), ci
    assert "pytest" in ci


def test_every_documented_command_is_complete_or_a_synopsis():
    incomplete = [f"{s.id}: {placeholders(s.text)}" for s in ALL_STEPS
                  if s.kind == "command" and not s.synopsis and placeholders(s.text)]
    assert not incomplete


def test_the_readme_links_every_page_of_docs():
    text = README.read_text(encoding="utf-8")
    pages = sorted(str(p.relative_to(ROOT)) for p in (ROOT / "docs").rglob("*.md"))
    assert pages
    assert [p for p in pages if f"]({p})" not in text] == []


def test_the_readme_is_a_front_door():
    """At most 200 lines; no lab history (dates, commit hashes)."""
    text = README.read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 200
    assert not re.findall(r"\b20\d\d-\d\d-\d\d\b", text)
    assert not re.findall(r"\b(?=[0-9a-f]*[a-f])(?=[0-9a-f]*\d)[0-9a-f]{7,40}\b", text)


# -- the first example: what its printed text says ---------------------------------------------

FIRST_EXAMPLE = "## A first example"


def python_example(text: str, heading: str = FIRST_EXAMPLE) -> str:
    """The first ```python block after ``heading`` (and before the next heading of its level)."""
    text = "\n" + text  # a heading on the first line too
    start = text.find(f"\n{heading}\n")
    assert start >= 0, f"README.md has no section '{heading}'"
    level = heading.split()[0]
    following = re.search(rf"\n{level} ", text[start + len(heading) + 2:])
    section = text[start:start + len(heading) + 2 + following.start()] if following else text[start:]
    block = re.search(r"\n```python\n(.*?)\n```\n", section, re.S)
    assert block, f"the README section '{heading}' has no ```python block"
    return block.group(1)


@pytest.fixture(scope="module")
def example(runs) -> dict:
    """The namespace of the README's first example (run once, with the other steps of the README)."""
    code = python_example(README.read_text(encoding="utf-8"))
    (step,) = [s for s in STEPS["README.md"] if s.kind == "python" and s.text == code]
    namespace = runs["README.md"].result(step)
    if isinstance(namespace, Exception):
        raise namespace
    return namespace


def test_first_example_roll_angle_decays_at_5_m_s(example):
    phi = example["result"]["phi"]
    assert phi[0] == pytest.approx(0.1, abs=1e-12)
    assert abs(phi[-1]) < 0.1 * abs(phi[0])  # self-stable at 5 m/s: the lean dies out


def test_first_example_compare_agrees_with_the_analytic_model(example):
    assert len(example["comparisons"]) == 3
    assert example["worst"] < 1e-9


def test_first_example_weave_mode_turns_stable_at_the_analytic_weave_speed(example):
    v = example["v_weave"]
    assert v == pytest.approx(4.292, abs=5e-4)  # Meijaard et al. (2007), Table 2
    below, above = example["weave"](v - 0.05), example["weave"](v + 0.05)
    assert below.shape == above.shape == (2,)
    assert np.all(below.real > 1e-3) and np.all(above.real < -1e-3)


def test_first_example_writes_nothing_into_the_working_directory(runs, example):
    """The FMUs went to COSIM_FMU_DIR: the commands' results are all the README's folder holds."""
    assert not (runs["README.md"].folder / "fmus").exists()


# -- the extractor itself -----------------------------------------------------------------------

def test_python_block_is_found_under_its_heading():
    text = ("# t\n\n## Other\n```python\nwrong = 1\n```\n\n"
            "## A first example\n\ntext\n\n```python\nx = 1\n```\n\n## Next\n")
    assert python_example(text) == "x = 1"
    with pytest.raises(AssertionError, match="has no ```python block"):
        python_example("## A first example\n\nno code\n\n## Next\n```python\ny = 2\n```\n")


MARKDOWN = """\
Run `cosim list` and `cosim info Bicycle.Bicycles.Whipple`; `cosim` alone and `cosim VERB: error` in a
sentence about synopsis `cosim build [MODEL ...]`.

```
cosim list
# a comment
python -m cosim.analytic.records --check
```

```
$ cosim compare X --speeds 2
header 1
...
last 3.5e-15
$ cosim list
```

A system file saved as `push.toml`:

```toml
[system]
stop = 1.0
```
"""


def test_markdown_extraction_finds_commands_outputs_and_blocks():
    steps = markdown_steps(MARKDOWN, "doc.md")
    assert [(s.kind, s.text, s.synopsis) for s in steps] == [
        ("command", "cosim list", False), ("command", "cosim info Bicycle.Bicycles.Whipple", False),
        ("command", "cosim VERB: error", False), ("command", "cosim build [MODEL ...]", True),
        ("command", "cosim list", False), ("command", "python -m cosim.analytic.records --check", False),
        ("command", "cosim compare X --speeds 2", False), ("command", "cosim list", False),
        ("toml", "[system]\nstop = 1.0", False)]
    assert steps[6].output == ["header 1", "...", "last 3.5e-15"] and steps[7].output == []
    assert steps[8].files == ["push.toml"] and "system file" in steps[8].context
    assert [s.line for s in steps] == [1, 1, 1, 2, 5, 7, 11, 15, 21]
    with pytest.raises(ValueError, match="no command"):
        markdown_steps("```\nsome output\n```\n", "doc.md")
    with pytest.raises(ValueError, match="no test knows how to run it"):
        markdown_steps("```rust\nfn main() {}\n```\n", "doc.md")


@pytest.mark.parametrize("command, found", [
    ("cosim build Bicycle.Bicycles.Whipple --fmi-version 2 3", []),
    ("cosim simulate MODEL --stop-time 5", ["MODEL"]),
    ("cosim info FMU|MODEL", ["|", "FMU", "MODEL"]),
    ("cosim build [MODEL ...]", ["...", "[", "]", "MODEL"]),
    ("cosim run SYSTEM.toml -o out.csv", ["SYSTEM"]),
    ("cosim simulate Bicycle.Bicycles.Whipple --param T_phi=1 --param V=5", []),
    ("pip install -e '.[test]' && cosim demo", []),
], ids=["complete", "model", "alternatives", "optional", "file", "parameters", "quoted"])
def test_placeholders(command, found):
    assert sorted(placeholders(command)) == sorted(found)


def test_output_is_compared_in_order_and_numbers_aside():
    printed = "title\nheader 1\nrow 1 2.0e-16\nrow 2 3.0e-16\nlast 1.60e-15\n"
    assert output_matches(["header 2", "...", "last 4.12e-15"], printed) == []
    assert output_matches(["last 1", "header 1"], printed) == ["header 1"]  # out of order
    assert output_matches(["footer"], printed) == ["footer"]


def test_guide_extraction_finds_classes_commands_and_their_files():
    text = ('<html><p>A model:</p>\n<pre>\nmodel V \\"a variant\\"\n  extends A;\nend V;\n</pre>\n'
            '<p>Save it as <code>lib/V.mo</code>; <code>cosim build V --library lib</code>, '
            '<code>cosim\ndiagram A</code>, <code>python -m x</code> and <code>Bicycle.A</code>.</p></html>')
    steps = guide_steps(text, "Guide.mo")
    assert [(s.kind, s.text) for s in steps] == [
        ("modelica", 'model V "a variant"\n  extends A;\nend V;'), ("command", "cosim build V --library lib"),
        ("command", "cosim diagram A"), ("command", "python -m x")]
    assert steps[0].files == ["lib/V.mo"]
