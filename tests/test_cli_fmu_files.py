"""Damaged and hostile FMU files: every verb answers with one message naming the file and the
problem (exit 2), never a traceback, and nothing is extracted outside the FMU's own folder."""
from __future__ import annotations

import io
import uuid
import zipfile
from pathlib import Path

import pytest

from conftest import run_cli

# the quick run (-m 'not slow') leaves this module out: it runs the command line in fresh processes
pytestmark = pytest.mark.slow

MODEL = "Bicycle.Bicycles.SelfStabilizing"
VERBS = ["info", "simulate", "linearize", "validate", "run"]


def _rewrite(original: bytes, change) -> bytes:
    """The archive with ``change(members)`` applied to its {name: bytes} members."""
    with zipfile.ZipFile(io.BytesIO(original)) as archive:
        members = {info.filename: archive.read(info) for info in archive.infolist()}
    change(members)
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as archive:
        for name, data in members.items():
            archive.writestr(zipfile.ZipInfo(name), data)
    return buffer.getvalue()


def _edit_xml(old: str, new: str):
    def change(members):
        members["modelDescription.xml"] = members["modelDescription.xml"].replace(old.encode(), new.encode(), 1)
    return change


def _cut_xml(members):
    xml = members["modelDescription.xml"]
    members["modelDescription.xml"] = xml[: len(xml) // 2]


def _drop_xml(members):
    del members["modelDescription.xml"]


# kind -> (how to damage the real FMU's bytes, fragment of the expected message)
DAMAGES = {
    "random-bytes": (lambda data: bytes(range(256)) * 8, "not a zip archive"),
    "truncated-zip": (lambda data: data[: len(data) // 2], "not a zip archive"),
    "missing-model-description": (lambda data: _rewrite(data, _drop_xml), "no modelDescription.xml"),
    "cut-model-description": (lambda data: _rewrite(data, _cut_xml), "modelDescription.xml is not well-formed XML"),
    "fmi-3.0": (lambda data: _rewrite(data, _edit_xml('fmiVersion="2.0"', 'fmiVersion="3.0"')),
                "FMI 3.0 FMUs are not supported yet"),
    "schema-violation": (lambda data: _rewrite(data, _edit_xml('causality="input"', 'causality="sideways"')),
                         "modelDescription.xml is invalid"),
}


def _command(verb: str, folder: Path, fmu: Path) -> tuple[list[str], Path | None]:
    """The command line of ``verb`` on ``fmu`` and the output it would write."""
    if verb == "simulate":
        out = folder / "out.csv"
        return ["simulate", str(fmu), "--stop-time", "0.5", "-o", str(out)], out
    if verb == "run":
        system = folder / "system.toml"
        system.write_text(f'connections = []\n[system]\nstop = 0.5\nstep = 0.1\n'
                          f'[components.bike]\nfmu = "{fmu.name}"\n')
        out = folder / "out.csv"
        return ["run", str(system), "-o", str(out)], out
    return [verb, str(fmu)], None


@pytest.mark.parametrize("verb", VERBS)
@pytest.mark.parametrize("kind", list(DAMAGES))
def test_unreadable_fmu_gets_one_message_naming_file_and_problem(fmus, tmp_path, kind, verb):
    damage, expected = DAMAGES[kind]
    if kind == "fmi-3.0":  # every verb reads FMI 3: an FMI 2 description relabelled 3.0 breaks its schema
        expected = "modelDescription.xml is invalid: ERROR"
    fmu = tmp_path / "model.fmu"
    fmu.write_bytes(damage(fmus[MODEL].read_bytes()))
    argv, out = _command(verb, tmp_path, fmu)
    result = run_cli(*argv, cwd=tmp_path)
    assert result.returncode == 2, result.stdout + result.stderr
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr, result.stderr
    errors = [line for line in result.stderr.splitlines() if line.startswith(f"cosim {verb}: error:")]
    assert len(errors) == 1, result.stderr
    assert str(fmu) in errors[0] and expected in errors[0], errors[0]
    assert out is None or not out.exists()


TRAVERSALS = {
    "parent": ("../{escape}", "points outside the FMU"),
    "nested-parent": ("binaries/../../{escape}", "points outside the FMU"),
    "absolute": ("/tmp/{escape}", "is an absolute path"),
    "backslash": ("..\\{escape}", "backslashes"),
}


@pytest.mark.parametrize("verb", ["validate", "linearize", "simulate", "info"])
@pytest.mark.parametrize("kind", list(TRAVERSALS))
def test_path_traversal_member_is_refused_before_extraction(fmus, tmp_path, kind, verb):
    """A member name that could land outside the extraction folder is refused; nothing is written
    outside (the real members are intact, so without the check the commands would succeed)."""
    escape = f"cosim-escape-{uuid.uuid4().hex}"
    name, expected = TRAVERSALS[kind]
    member = name.format(escape=escape)
    work = tmp_path / "work"
    work.mkdir()
    fmu = work / "model.fmu"
    fmu.write_bytes(_rewrite(fmus[MODEL].read_bytes(), lambda members: members.update({member: b"escaped"})))
    argv, out = _command(verb, work, fmu)
    result = run_cli(*argv, cwd=work)
    assert result.returncode == 2, result.stdout + result.stderr
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr, result.stderr
    assert f"unsafe member name '{member}'" in result.stderr and expected in result.stderr, result.stderr
    for place in (tmp_path, Path("/tmp"), Path.cwd(), Path("/")):
        assert not list(place.glob(f"{escape}*")), f"{escape} escaped into {place}"
    assert out is None or not out.exists()


def test_fmu_without_binary_for_this_platform_is_named(fmus, tmp_path):
    """Reading the interface works (info), running needs the binary: the message says which is missing."""
    fmu = tmp_path / "nobinary.fmu"
    fmu.write_bytes(_rewrite(fmus[MODEL].read_bytes(),
                             lambda m: [m.pop(n) for n in [n for n in m if n.startswith("binaries/")]]))
    assert run_cli("info", str(fmu)).returncode == 0
    out = tmp_path / "out.csv"
    result = run_cli("simulate", str(fmu), "--stop-time", "0.5", "-o", str(out))
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert "no binary for this platform" in result.stderr and "binaries/linux64/" in result.stderr
    assert not out.exists()


def test_fmu_that_is_a_directory_is_named(tmp_path):
    folder = tmp_path / "folder.fmu"
    folder.mkdir()
    result = run_cli("info", str(folder))
    assert result.returncode == 2 and f"{folder}: is a directory, not an FMU file" in result.stderr


def test_version_check_is_one_place():
    """FMI 3 support will change one function: cosim.fmu.access.check_fmi_version."""
    from cosim.errors import FMUError
    from cosim.fmu.access import SUPPORTED_FMI_VERSIONS, check_fmi_version

    assert SUPPORTED_FMI_VERSIONS == ("2.0",)
    check_fmi_version(Path("x.fmu"), "2.0")
    for version, message in (("3.0", "FMI 3.0 FMUs are not supported yet"), ("1.0", "FMI version '1.0'"),
                             (None, "no fmiVersion")):
        with pytest.raises(FMUError, match=message):
            check_fmi_version(Path("x.fmu"), version)
