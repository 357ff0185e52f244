"""The shell pipelines in cli/."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from ptailor.samples.obj_text import sample_obj_text

CLI = Path(__file__).resolve().parents[1] / "cli"


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("xargs") is None, reason="needs xargs")
def test_adjust_each_runs_every_garment_and_reports_failures(tmp_path):
    good = []
    for k in range(3):
        p = tmp_path / f"g{k}.obj"
        p.write_text(sample_obj_text("lantern_sleeve"))
        good.append(p)
    bad = tmp_path / "broken.obj"
    bad.write_text("not a garment\n")
    rec = tmp_path / "r.yaml"
    rec.write_text("steps: [{op: scale, factor: 1.1}]\n")
    out = tmp_path / "out"
    env = dict(os.environ, JOBS="2", PTAILOR=f"{sys.executable} -m ptailor")
    paths = "\n".join(str(p) for p in [*good, bad]) + "\n"
    r = subprocess.run(
        [str(CLI / "adjust-each"), str(rec), str(out)],
        input=paths,
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert r.returncode == 1, r.stderr
    assert sorted(p.name for p in out.iterdir()) == ["g0", "g1", "g2"]
    for k in range(3):
        rep = json.loads((out / f"g{k}" / "report.json").read_text())
        assert rep["panels"][0]["area_after"] > rep["panels"][0]["area_before"]
    assert "broken.obj" in r.stderr and "not an OBJ" in r.stderr


def _catalogue(root: Path) -> None:
    """Generated garments in nested folders, and one broken file."""
    (root / "tops").mkdir(parents=True)
    (root / "skirts" / "long").mkdir(parents=True)
    (root / "tops" / "sleeve.obj").write_text(sample_obj_text("lantern_sleeve"))
    (root / "tops" / "tube.obj").write_text(sample_obj_text("cylinder"))
    (root / "skirts" / "long" / "skirt.obj").write_text(sample_obj_text("cone_skirt"))
    (root / "skirts" / "broken.obj").write_text("not a garment\n")


def _ptailor_env(**extra: str) -> dict:
    return dict(os.environ, PTAILOR=f"{sys.executable} -m ptailor", PYTHON=sys.executable, **extra)


@pytest.mark.slow
def test_adjust_catalogue_finds_garments_and_writes_a_csv_summary(tmp_path):
    import csv

    from ptailor.batch import RECORD_KEYS

    cat = tmp_path / "cat"
    _catalogue(cat)
    rec = tmp_path / "r.yaml"
    rec.write_text("steps: [{op: scale, factor: 1.2}]\n")
    out = cat / "out"  # inside the catalogue: its garment.obj files are not garments
    cmd = [str(CLI / "adjust-catalogue"), str(rec), str(cat), str(out), "-j", "2", "-q"]
    env = _ptailor_env()
    rows = None
    for run, expect in ((1, "ok"), (2, "skipped")):
        r = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=300)
        assert r.returncode == 1, (run, r.stderr)
        assert sorted(p.name for p in out.iterdir()) == [
            "batch.jsonl",
            "skirt",
            "sleeve",
            "summary.csv",
            "tube",
        ]
        with open(out / "summary.csv", newline="") as f:
            reader = csv.DictReader(f)
            assert tuple(reader.fieldnames) == RECORD_KEYS
            rows = list(reader)
        # sorted paths: skirts/broken, skirts/long/skirt, tops/sleeve, tops/tube
        assert [Path(x["garment"]).name for x in rows] == [
            "broken.obj",
            "skirt.obj",
            "sleeve.obj",
            "tube.obj",
        ]
        assert [x["status"] for x in rows] == ["failed", expect, expect, expect]
        assert rows[0]["failure"] == "input" and "not an OBJ" in rows[0]["reason"]
        assert rows[0]["panels"] == "" and rows[0]["out"].endswith("broken")
        assert float(rows[2]["max_area_change"]) == pytest.approx(0.44, abs=1e-4)  # 1.2 x 1.2
        assert rows[2]["panels"] == "2" and rows[2]["flipped_triangles"] == "0"
        assert "broken.obj" in r.stderr and "summary.csv" in r.stderr
    assert (out / "sleeve" / "report.json").is_file()
    # usage
    r = subprocess.run([str(CLI / "adjust-catalogue"), "--help"], capture_output=True, text=True)
    assert r.returncode == 0 and "summary.csv" in r.stdout
    r = subprocess.run([str(CLI / "adjust-catalogue"), str(rec)], capture_output=True, text=True)
    assert r.returncode == 2 and "OUTROOT" in r.stderr


def _adjust_parallel(tmp_path, env: dict) -> subprocess.CompletedProcess:
    cat = tmp_path / "cat"
    _catalogue(cat)
    rec = tmp_path / "r.yaml"
    rec.write_text("steps: [{op: scale, factor: 1.2}]\n")
    paths = sorted(str(p) for p in cat.rglob("*.obj"))
    return subprocess.run(
        [str(CLI / "adjust-parallel"), str(rec), str(tmp_path / "out")],
        input="\n".join(paths) + "\n\n",
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )


def _check_adjust_parallel(tmp_path, r) -> None:
    assert r.returncode == 1, r.stderr
    out = tmp_path / "out"
    assert sorted(p.name for p in out.iterdir()) == ["skirt", "sleeve", "tube"], r.stderr
    for name in ("skirt", "sleeve", "tube"):
        rep = json.loads((out / name / "report.json").read_text())
        assert rep["panels"][0]["area_after"] > rep["panels"][0]["area_before"]
    ok = sorted(ln.split("\t") for ln in r.stdout.splitlines())
    assert [(Path(g).name, Path(o).name, s) for s, g, o in ok] == [
        ("skirt.obj", "skirt", "ok"),
        ("sleeve.obj", "sleeve", "ok"),
        ("tube.obj", "tube", "ok"),
    ]
    assert "failed\t" in r.stderr and "broken.obj" in r.stderr and "not an OBJ" in r.stderr


@pytest.mark.slow
def test_adjust_parallel_falls_back_to_xargs_without_gnu_parallel(tmp_path):
    # a `parallel` that is not GNU parallel (moreutils has one): must not be used
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    fake = bin_dir / "parallel"
    fake.write_text(
        f"#!/bin/sh\n[ \"$1\" = --version ] && {{ echo 'parallel [OPTIONS]'; exit 1; }}\n"
        f"touch {tmp_path / 'fake-used'}\nexit 1\n"
    )
    fake.chmod(0o755)
    env = _ptailor_env(JOBS="2", PATH=f"{bin_dir}{os.pathsep}{os.environ['PATH']}")
    r = _adjust_parallel(tmp_path, env)
    _check_adjust_parallel(tmp_path, r)
    assert not (tmp_path / "fake-used").exists()
    # arguments: repeated names, no garments, usage
    rec = tmp_path / "r.yaml"
    a, b = tmp_path / "cat" / "tops" / "tube.obj", tmp_path / "tube.obj"
    shutil.copy(a, b)
    r = subprocess.run(
        [str(CLI / "adjust-parallel"), str(rec), str(tmp_path / "o2"), str(a), str(b)],
        capture_output=True,
        text=True,
        env=env,
    )
    assert r.returncode == 2 and "repeat (tube)" in r.stderr
    assert not (tmp_path / "o2").exists()
    r = subprocess.run(
        [str(CLI / "adjust-parallel"), str(rec), str(tmp_path / "o2")],
        input="\n",
        capture_output=True,
        text=True,
        env=env,
    )
    assert r.returncode == 2 and "no garments" in r.stderr
    r = subprocess.run([str(CLI / "adjust-parallel"), "-h"], capture_output=True, text=True)
    assert r.returncode == 0 and "xargs" in r.stdout


def _gnu_parallel() -> bool:
    if shutil.which("parallel") is None:
        return False
    r = subprocess.run(["parallel", "--version"], capture_output=True, text=True)
    return "GNU parallel" in r.stdout


@pytest.mark.skipif(not _gnu_parallel(), reason="needs GNU parallel")
def test_adjust_parallel_with_gnu_parallel(tmp_path):
    r = _adjust_parallel(tmp_path, _ptailor_env(JOBS="2", PARALLEL_TOOL="parallel"))
    _check_adjust_parallel(tmp_path, r)


# ptailor batch itself finds a batch.jsonl, after it starts (1.1 s of CPU): slow
@pytest.mark.parametrize(
    "name", ["summary.csv", pytest.param("batch.jsonl", marks=pytest.mark.slow)]
)
def test_adjust_catalogue_leaves_a_users_files_in_outroot_alone(tmp_path, name):
    """Issue 22: the script removed OUTROOT/batch.jsonl and wrote OUTROOT/summary.csv over
    whatever they were. A file of either name that the tools did not write is exit 2,
    untouched, before any garment runs."""
    cat = tmp_path / "cat"
    _catalogue(cat)
    rec = tmp_path / "r.yaml"
    rec.write_text("steps: [{op: scale, factor: 1.2}]\n")
    out = tmp_path / "out"
    out.mkdir()
    mine = out / name
    mine.write_text("my,own,table\n1,2,3\n")
    cmd = [str(CLI / "adjust-catalogue"), str(rec), str(cat), str(out), "-q"]
    r = subprocess.run(cmd, capture_output=True, text=True, env=_ptailor_env(), timeout=300)
    assert r.returncode == 2, r.stderr
    assert name in r.stderr
    assert mine.read_text() == "my,own,table\n1,2,3\n"
    assert sorted(p.name for p in out.iterdir()) == [name]


def _adjust_catalogue(*args, timeout: float = 300) -> subprocess.CompletedProcess:
    cmd = [str(CLI / "adjust-catalogue"), *[str(a) for a in args]]
    return subprocess.run(cmd, capture_output=True, text=True, env=_ptailor_env(), timeout=timeout)


def _linked_catalogue(tmp_path: Path) -> tuple[Path, Path]:
    """A catalogue whose garments are reached only through symbolic links: a link to an OBJ
    and a link to a folder of them (as catalogues shared between teams are often built)."""
    store = tmp_path / "store"
    (store / "skirts").mkdir(parents=True)
    (store / "sleeve.obj").write_text(sample_obj_text("lantern_sleeve"))
    (store / "skirts" / "skirt.obj").write_text(sample_obj_text("cone_skirt"))
    cat = tmp_path / "cat"
    cat.mkdir()
    (cat / "sleeve.obj").symlink_to(store / "sleeve.obj")
    (cat / "skirts").symlink_to(store / "skirts", target_is_directory=True)
    rec = tmp_path / "r.yaml"
    rec.write_text("steps: [{op: scale, factor: 1.2}]\n")
    return cat, rec


@pytest.mark.slow
def test_adjust_catalogue_follows_symbolic_links(tmp_path):
    """Issue 24: `find -type f` skipped OBJs reached through links (exit 2, no garments).
    A link to OUTROOT inside the catalogue does not make its outputs garments."""
    cat, rec = _linked_catalogue(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    (cat / "results").symlink_to(out, target_is_directory=True)
    for expect in ("ok", "skipped"):
        r = _adjust_catalogue(rec, cat, out, "-j", "1", "-q")
        assert r.returncode == 0, r.stderr
        recs = [json.loads(ln) for ln in (out / "batch.jsonl").read_text().splitlines()]
        assert [Path(x["garment"]).name for x in recs] == ["skirt.obj", "sleeve.obj"]
        assert [x["status"] for x in recs] == [expect, expect]
    assert sorted(p.name for p in out.iterdir()) == [
        "batch.jsonl",
        "skirt",
        "sleeve",
        "summary.csv",
    ]


@pytest.mark.slow
def test_adjust_catalogue_writes_a_manifest_that_batch_takes(tmp_path):
    import csv

    from tests.test_pattern_io import _setup

    cat, rec = _linked_catalogue(tmp_path)
    _setup(cat)  # cat/lantern_sleeve.dxf + its drape cat/lantern_sleeve.obj: one garment
    out = tmp_path / "out"
    manifest = cat / "units.csv"
    r = _adjust_catalogue(rec, cat, out, "-j", "1", "--write-manifest", manifest)
    assert r.returncode == 0, r.stderr
    assert "--manifest" in r.stderr and not out.exists()  # nothing run
    with open(manifest, newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == ["garment", "pattern_units", "drape_units", "dxf_units"]
    # relative to the manifest's folder; the DXF's drape is not a garment of its own
    assert [x["garment"] for x in rows] == ["lantern_sleeve.dxf", "skirts/skirt.obj", "sleeve.obj"]
    assert all(x["pattern_units"] == x["drape_units"] == x["dxf_units"] == "" for x in rows)
    # a user fills in a unit; batch takes the manifest
    rows[0]["dxf_units"] = "mm"
    with open(manifest, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    batch = [sys.executable, "-m", "ptailor", "batch", str(rec), "--manifest", str(manifest)]
    batch += ["-o", str(out), "-j", "1", "--json", "-q", "--formats", "obj"]
    r = subprocess.run(batch, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    recs = [json.loads(ln) for ln in r.stdout.splitlines()]
    assert [x["status"] for x in recs] == ["ok"] * 3
    stamp = json.loads((out / "lantern_sleeve" / "batch.json").read_text())
    assert stamp["options"]["dxf_units"] == "mm"
    # an existing manifest (the user's edits) is never replaced; no garments: exit 2
    before = manifest.read_bytes()
    r = _adjust_catalogue(rec, cat, out, f"--write-manifest={manifest}", timeout=60)
    assert r.returncode == 2 and "exists" in r.stderr and manifest.read_bytes() == before
    empty, other = tmp_path / "empty", tmp_path / "other.csv"
    empty.mkdir()
    r = _adjust_catalogue(rec, empty, out, "--write-manifest", other, timeout=60)
    assert r.returncode == 2 and "no garments" in r.stderr and not other.exists()
    r = _adjust_catalogue("--help", timeout=60)
    assert "--write-manifest FILE" in r.stdout and "symbolic links" in r.stdout.lower()
