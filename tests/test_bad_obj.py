"""Bad OBJ inputs (issue 12): every signature of the fuzzing campaign as a regression test.

The contract: exit 0, or exit 2 with one line naming the file and the problem and nothing
written. The hand-made files are in ``tests/corpus/obj`` (a two-triangle square, one fault
each); the long ones and the garment-sized ones are generated here.
"""

from __future__ import annotations

import contextlib
import json
import time
import warnings
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from ptailor import tolerances as tol
from ptailor.cli.main import cli
from ptailor.errors import PtailorError
from ptailor.formats.obj import read_obj, write_obj
from ptailor.samples.obj_text import sample_obj_text

CORPUS = Path(__file__).parent / "corpus" / "obj"
RECIPE = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]\n"

#: corpus file -> None (exit 0) or a fragment of the exit-2 message
EXPECTED = {
    "ok_square.obj": None,
    "bom.obj": None,
    "crlf.obj": None,
    "negative_indices.obj": None,
    "all_faces_duplicated.obj": None,
    "one_face_duplicated.obj": None,
    "unreferenced_vt_first.obj": None,
    "coord_1e300.obj": "'v' record 3: coordinate 1e+300 is beyond",
    "coord_inf_vt.obj": "'vt' record 3: coordinate inf is NaN or infinite",
    "unreferenced_nan_v.obj": "'v' record 5: coordinate nan is NaN or infinite",
    "face_index_1e20.obj": "face refers to a missing vertex",
    "face_index_zero.obj": "missing 'v' (index 0 out of range",
    "face_index_negative_past.obj": "missing 'v' (index -5 out of range",
    "face_index_past_end.obj": "missing 'v' (index 9 out of range",
    "vt_index_past_end.obj": "missing 'vt' (index 9 out of range",
    "empty.obj": "no 'v' or no 'f' records",
    "text_junk.obj": "no 'v' or no 'f' records",
    "binary_junk.obj": "binary content",
    # issue 22: one short record once cut every record to its length (the drape lost z)
    "v_without_z.obj": "'v' record 2 has 2 value(s), needs 3: '10 0'",
    "v_all_without_z.obj": "'v' record 1 has 2 value(s), needs 3",
    "vt_one_value.obj": "'vt' record 2 has 1 value(s), needs 2",
    "v_with_w.obj": None,
    "v_bare_line.obj": "'v' record 3 has 0 value(s), needs 3 (1",  # skipped, it shifted indices
}


@pytest.fixture
def recipe(tmp_path) -> Path:
    p = tmp_path / "r.yaml"
    p.write_text(RECIPE)
    return p


def _adjust(garment: Path, recipe: Path, out: Path, *extra: str):
    args = ["adjust", str(garment), str(recipe), "-o", str(out), "--formats", "obj,dxf,svg,png"]
    return CliRunner().invoke(cli, [*args, *extra])


def assert_contract(r, out: Path, path: Path | str, fragment: str | None = None) -> None:
    """Exit 0 with finite outputs, or exit 2: one line naming the file, nothing written."""
    assert r.exit_code in (0, 2), (r.exit_code, r.output, r.exception)
    if r.exit_code == 2:
        lines = [ln for ln in r.output.splitlines() if ln.strip()]
        assert len(lines) == 1, r.output
        assert str(path) in lines[0], r.output
        assert "Warning" not in r.output
        if fragment:
            assert fragment in lines[0], r.output
        assert not out.exists()
    else:
        assert fragment is None, f"expected exit 2 ({fragment}), got 0"
        assert_no_nan_written(out)


def assert_no_nan_written(out: Path) -> None:
    for name in ("garment.obj", "report.json", "pattern.svg"):
        f = out / name
        if f.exists():
            text = f.read_text().lower()
            assert "nan" not in text and "inf" not in text.replace("info", ""), name


def test_corpus_is_complete():
    assert sorted(EXPECTED) == sorted(p.name for p in CORPUS.glob("*.obj"))


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_corpus_adjust_and_inspect(name, recipe, tmp_path):
    path = CORPUS / name
    out = tmp_path / "out"
    units = ("--drape-units", "cm", "--pattern-units", "cm")  # 10 cm squares: units given
    assert_contract(_adjust(path, recipe, out, *units), out, path, EXPECTED[name])
    r = CliRunner().invoke(cli, ["inspect", str(path), *units])
    assert r.exit_code == (0 if EXPECTED[name] is None else 2), r.output
    if r.exit_code == 2:
        assert str(path) in r.output and len(r.output.strip().splitlines()) == 1


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_reader_prints_no_warnings(name):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with contextlib.suppress(PtailorError):
            read_obj(CORPUS / name)
    assert not caught, [str(w.message) for w in caught]


def test_bom_and_crlf_read_as_the_plain_file():
    plain = read_obj(CORPUS / "ok_square.obj")
    for name in ("bom.obj", "crlf.obj"):
        m = read_obj(CORPUS / name)
        np.testing.assert_array_equal(m.v, plain.v)
        np.testing.assert_array_equal(m.fvt, plain.fvt)
        assert m.group_names == plain.group_names == ("panel",)
        assert m.header == plain.header


@pytest.mark.slow
def test_bom_and_crlf_sleeve_give_the_same_garment(tmp_path, recipe):
    text = sample_obj_text("lantern_sleeve")
    variants = {
        "plain": text.encode(),
        "bom": b"\xef\xbb\xbf" + text.encode(),
        "crlf": text.replace("\n", "\r\n").encode(),
        "bom_crlf": b"\xef\xbb\xbf" + text.replace("\n", "\r\n").encode(),
        "cr": text.replace("\n", "\r").encode(),
    }
    results = {}
    for key, data in variants.items():
        src = tmp_path / f"{key}.obj"
        src.write_bytes(data)
        out = tmp_path / f"out_{key}"
        r = _adjust(src, recipe, out, "--formats", "obj")
        assert r.exit_code == 0, r.output
        results[key] = (out / "garment.obj").read_text()
    assert len(set(results.values())) == 1


@pytest.mark.slow
def test_unreferenced_vt_before_the_used_ones(tmp_path, recipe):
    """The ``component_labels`` (once ``face_components``) IndexError: unused ``vt`` first."""
    text = sample_obj_text("lantern_sleeve")
    lines = text.splitlines(keepends=True)
    first_vt = next(i for i, ln in enumerate(lines) if ln.startswith("vt "))
    extra = "vt 1 2\nvt 3 4\nvt 5 6\n"

    def shift(ln: str) -> str:  # every vt index moves by 3
        if not ln.startswith("f "):
            return ln
        corners = [c.split("/") for c in ln.split()[1:]]
        return "f " + " ".join(f"{a}/{int(b) + 3}" for a, b in corners) + "\n"

    src = tmp_path / "s.obj"
    src.write_text(
        "".join(lines[:first_vt]) + extra + "".join(shift(ln) for ln in lines[first_vt:])
    )
    out = tmp_path / "out"
    r = _adjust(src, recipe, out)
    assert r.exit_code == 0, r.output
    assert_no_nan_written(out)


@pytest.mark.slow
@pytest.mark.parametrize("which", ["every", "one"])
def test_duplicated_faces_all_formats(which, tmp_path, recipe):
    """``zero-size array`` in ``marks.mesh_pieces`` (every face twice) and the ``(k, 2)``
    outline error of the preview (one face twice): the intake drops the copies."""
    text = sample_obj_text("lantern_sleeve")
    faces = [ln for ln in text.splitlines(keepends=True) if ln.startswith("f ")]
    src = tmp_path / "s.obj"
    src.write_text(text + ("".join(faces) if which == "every" else faces[5]))
    out = tmp_path / "out"
    r = _adjust(src, recipe, out, "--json")
    assert r.exit_code == 0, r.output
    assert_no_nan_written(out)
    rep = json.loads((out / "report.json").read_text())
    assert "duplicate" in json.dumps(rep)
    r = CliRunner().invoke(cli, ["inspect", str(src)])
    assert r.exit_code == 0, r.output


def test_long_group_name_is_refused_fast(tmp_path, recipe):
    """A 1 MB group name hung the PNG writer: names are bounded when read."""
    text = (CORPUS / "ok_square.obj").read_text()
    for n in (tol.OBJ_MAX_NAME + 1, 50_000, 1_000_000):
        src = tmp_path / f"long{n}.obj"
        src.write_text(text.replace("g panel", "g " + "x" * n))
        out = tmp_path / f"out{n}"
        t0 = time.perf_counter()
        r = _adjust(src, recipe, out)
        assert time.perf_counter() - t0 < 10
        frag = "group name" if n < tol.OBJ_MAX_LINE else "bytes long"
        assert_contract(r, out, src, frag)
    ok = tmp_path / "ok.obj"
    ok.write_text(text.replace("g panel", "g " + "n" * tol.OBJ_MAX_NAME))
    assert read_obj(ok).group_names == ("n" * tol.OBJ_MAX_NAME,)


def test_preview_shortens_long_panel_names():
    from ptailor.formats.preview import check_inputs

    sq = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    pat = check_inputs([[sq]], [[sq]], ["y" * 100_000])
    assert len(pat.names[0]) == tol.PREVIEW_NAME_MAX


def test_long_line_and_big_file_and_many_triangles(tmp_path, monkeypatch, recipe):
    text = (CORPUS / "ok_square.obj").read_text()
    src = tmp_path / "longline.obj"
    src.write_text(text + "# " + "y" * (tol.OBJ_MAX_LINE + 1) + "\n")
    with pytest.raises(PtailorError, match=r"line 13 is \d+ bytes long"):
        read_obj(src)
    monkeypatch.setattr(tol, "OBJ_MAX_BYTES", 100)
    with pytest.raises(PtailorError, match="larger than the 100 bytes"):
        read_obj(CORPUS / "ok_square.obj")
    monkeypatch.setattr(tol, "OBJ_MAX_BYTES", 1 << 30)
    monkeypatch.setattr(tol, "OBJ_MAX_TRIANGLES", 1)
    with pytest.raises(PtailorError, match="2 triangles: more than the 1"):
        read_obj(CORPUS / "ok_square.obj")
    out = tmp_path / "out"
    assert_contract(_adjust(CORPUS / "ok_square.obj", recipe, out), out, CORPUS / "ok_square.obj")


def test_coordinate_limit_is_inclusive(tmp_path):
    text = (CORPUS / "ok_square.obj").read_text()
    src = tmp_path / "big.obj"
    src.write_text(text.replace("v 10 10 0", f"v {tol.OBJ_COORD_MAX:g} 10 0"))
    assert read_obj(src).v.max() == tol.OBJ_COORD_MAX
    src.write_text(text.replace("v 10 10 0", "v -1e300 10 0"))
    with pytest.raises(PtailorError, match="beyond"):
        read_obj(src)


def test_writer_never_writes_nan(tmp_path):
    V3 = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [np.nan, np.nan, np.nan]])
    V2 = np.array([[0.0, 0], [1, 0], [0, 1]])
    F = np.array([[0, 1, 2]])
    with pytest.raises(PtailorError, match="non-finite 'v'"):
        write_obj(
            tmp_path / "g.obj", V3=V3, F3=F, V2=V2, F2=F, face_panel=np.zeros(1, int),
            panel_names=["p"],
        )  # fmt: skip
    assert not (tmp_path / "g.obj").exists()


@pytest.mark.parametrize(
    "option, value",
    [
        ("--pattern-units", "1e300cm"),
        ("--pattern-units", "0cm"),
        ("--pattern-units", "1e-300mm"),
        ("--drape-units", "1e300cm"),
        ("--drape-units", "0.0m"),
        ("--seam-allowance", "1e300"),
        ("--weld", "1e300"),
    ],
)
def test_options_out_of_range(option, value, tmp_path, recipe):
    src = CORPUS / "ok_square.obj"
    out = tmp_path / "out"
    r = _adjust(src, recipe, out, option, value)
    assert r.exit_code == 2, r.output
    assert len(r.output.strip().splitlines()) == 1 and option in r.output
    assert not out.exists()


def test_scaled_units_in_range_still_work(tmp_path, recipe):
    out = tmp_path / "out"
    r = _adjust(CORPUS / "ok_square.obj", recipe, out, "--pattern-units", "0.25cm")
    assert r.exit_code == 2 and "disagree in scale" in r.output  # a ratio check, not a crash
    r = _adjust(
        CORPUS / "ok_square.obj", recipe, out, "--pattern-units", "10mm", "--drape-units", "1cm"
    )
    assert r.exit_code == 0, r.output


# --body: garbage bodies


def _bodies(tmp_path: Path) -> dict[str, Path]:
    rng = np.random.default_rng(1)
    data = {
        "empty.obj": b"",
        "junk.obj": rng.bytes(3000),
        "junk.stl": rng.bytes(3000),
        "junk.ply": rng.bytes(600),
        "text.obj": b"hello\nworld\n",
        "text.stl": b"hello\nworld\n",
        "nan.obj": b"v nan 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n",
        "open.obj": b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        "body.xyz": b"abc",
    }
    out = {}
    for name, b in data.items():
        out[name] = tmp_path / name
        out[name].write_bytes(b)
    return out


def test_read_body_garbage(tmp_path):
    from ptailor.edits.body import read_body

    for name, p in _bodies(tmp_path).items():
        with pytest.raises(PtailorError) as exc:
            read_body(str(p), units="cm", to="cm")
        msg = str(exc.value)
        assert str(p) in msg and "\n" not in msg, name
        assert "module" not in msg.lower(), msg
    assert "not closed" in _msg(read_body, tmp_path / "open.obj")
    assert "finite" in _msg(read_body, tmp_path / "nan.obj")


def _msg(fn, p: Path) -> str:
    try:
        fn(str(p), units="cm", to="cm")
    except PtailorError as exc:
        return str(exc)
    return ""


def test_read_body_closed_meshes(tmp_path):
    import trimesh

    from ptailor.edits.body import read_body

    sphere = trimesh.creation.icosphere(subdivisions=2, radius=20.0)
    for ext in ("obj", "stl", "ply", "off"):
        p = tmp_path / f"sphere.{ext}"
        sphere.export(p)
        m = read_body(str(p), units="cm", to="mm")
        assert m.is_watertight and len(m.faces) == len(sphere.faces), ext
        assert np.isclose(np.abs(m.vertices).max(), 200.0)


def _body_cli(tmp_path: Path, names) -> list:
    src = tmp_path / "s.obj"
    src.write_text(sample_obj_text("cone_skirt"))
    rec = tmp_path / "r.yaml"
    rec.write_text("steps: [{op: extend, opening: hem, by: 3}]\n")
    results = []
    for name, p in _bodies(tmp_path).items():
        if name not in names:
            continue
        out = tmp_path / f"o_{name}"
        args = ["adjust", str(src), str(rec), "--body", str(p), "-o", str(out)]
        results.append((name, p, out, CliRunner().invoke(cli, args)))
    return results


def test_body_option_garbage_exits_2(tmp_path):
    names = ["empty.obj", "junk.obj", "junk.stl", "junk.ply", "text.obj", "text.stl", "body.xyz"]
    for name, p, out, r in _body_cli(tmp_path, names):
        assert r.exit_code == 2, (name, r.output)
        assert str(p) in r.output and len(r.output.strip().splitlines()) == 1, r.output
        assert not out.exists()


def test_body_option_messages_are_clear(tmp_path):
    for name, _p, out, r in _body_cli(tmp_path, ["junk.obj", "junk.stl", "nan.obj", "open.obj"]):
        assert r.exit_code == 2, (name, r.output)
        assert "module" not in r.output.lower(), r.output
        assert not out.exists()


@pytest.mark.slow
def test_a_flat_drape_ends_with_a_warning_that_says_why(tmp_path, recipe):
    """Issue 22: the demo sleeve with every z = 0 (what one short record once made of it):
    the weld joins the tube's two layers and the seam rows become dependent; each step
    repeated a least-squares solve of the whole seam system (20 s each, > 200 s in all).
    Now the singular system is factored once with a tiny ridge (11 s in all), and the
    warning says what failed, not a cap that was never reached."""
    lines = sample_obj_text("lantern_sleeve").splitlines()
    flat = [" ".join([*ln.split()[:3], "0"]) if ln.startswith("v ") else ln for ln in lines]
    path = tmp_path / "flat.obj"
    path.write_text("\n".join(flat) + "\n")
    out = tmp_path / "out"
    r = _adjust(path, recipe, out, "--no-baseline")
    assert r.exit_code == 0, r.output
    assert "iteration cap" not in r.output and "panel  still" not in r.output
    assert "seam constraints met only to" in r.output


def test_a_singular_seam_system_is_factored_once_without_least_squares(monkeypatch):
    from ptailor.method.solver.small_systems import bordered_solver, spd_factor

    rng = np.random.default_rng(0)
    G = rng.normal(size=(40, 25))
    M = G @ G.T  # rank 25 of 40: dependent rows
    r = M @ rng.normal(size=40)  # consistent

    def no_lstsq(*a, **k):
        raise AssertionError("least squares")

    monkeypatch.setattr(np.linalg, "lstsq", no_lstsq)
    for solve in (spd_factor(M), bordered_solver(M, None)):
        x = solve(r)
        assert np.linalg.norm(M @ x - r) < 1e-6 * np.linalg.norm(r)
    B = np.zeros((40, 1))
    B[:10, 0] = 1.0
    u = bordered_solver(M, B)(r)
    assert u is not None and np.all(np.isfinite(u))


def _obj(V, F) -> bytes:
    lines = [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in V]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in F]
    return ("\n".join(lines) + "\n").encode()


def test_read_body_refuses_what_is_not_a_body(tmp_path):
    """Closed is not enough: a body encloses a volume with its faces pointing out."""
    import trimesh

    from ptailor.edits.body import read_body

    sphere = trimesh.creation.icosphere(subdivisions=2, radius=20.0)
    V, F = np.asarray(sphere.vertices), np.asarray(sphere.faces)
    flipped = F.copy()
    flipped[:7] = flipped[:7, ::-1]
    flat = np.c_[V[:, 0], V[:, 1], 0.0 * V[:, 2]]  # a doubled disc: closed, no volume
    cases = {
        "point.obj": (b"v 1 2 3\nv 1 2 3\nv 1 2 3\nf 1 2 3\n", "no proper triangles"),
        "inside_out.obj": (_obj(V, F[:, ::-1]), "inside out"),
        "mixed.obj": (_obj(V, flipped), "not consistently oriented"),
        "flat.obj": (_obj(flat, F), "encloses almost no volume"),
    }
    for name, (data, words) in cases.items():
        p = tmp_path / name
        p.write_bytes(data)
        msg = _msg(read_body, p)
        assert str(p) in msg and words in msg, (name, msg)
    # the sphere itself, and the same with a few degenerate triangles added, are bodies
    p = tmp_path / "sphere_plus.obj"
    p.write_bytes(_obj(V, np.r_[F, [[0, 0, 1], [2, 2, 2]]]))
    m = read_body(str(p), units="cm", to="cm")
    assert len(m.faces) == len(F) and m.volume > 0.9 * 4.0 / 3.0 * np.pi * 20.0**3


def test_the_shared_bodies_are_bodies():
    from ptailor.edits.body import read_body

    for name in ("mean_all.obj", "mean_all_tpose.obj"):
        path = Path(__file__).resolve().parents[2] / "shared" / "bodies" / name
        if not path.is_file():
            pytest.skip("../shared is absent")
        m = read_body(str(path), units="cm", to="cm")
        assert m.is_winding_consistent and m.volume > 0.0
