"""The catalogue a person looks at: ``ptailor batch --html`` and ``ptailor report OUT``.

Rows, statuses, reasons and gates; every link and picture relative and present; names from
files escaped; the garment folders still replaceable by a later run; bad targets exit 2
with nothing written. The page in a real browser: ``test_catalogue_browser.py``.
"""

from __future__ import annotations

import json
import shutil
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest
from click.testing import CliRunner

from ptailor.batch import output_names
from ptailor.batch.manifest import read_manifest
from ptailor.catalogue import CATALOGUE_DIR, Summary, catalogue_rows, read_log, write_catalogue
from ptailor.catalogue.pages import link, shown, shown_number
from ptailor.cli.main import cli
from ptailor.errors import PtailorError
from ptailor.formats.obj import write_garment
from ptailor.run.folder import MARKER, check_output_dir, read_marker
from ptailor.samples import cone_skirt, cylinder, lantern_sleeve

WIDER = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]\n"
#: the skirt breaks both (area change 0.22, outline deviation 4.0), the sleeve the second
#: (2.3); the tube passes (0.2, 1.8)
GATES = ("--max-area-change", "0.21", "--max-boundary-deviation", "2.0")
#: a name that is markup: it must show as text
MARKUP = "<script>alert(1)</script>"


def run(*args, input=None):
    return CliRunner().invoke(cli, [str(a) for a in args], input=input, catch_exceptions=False)


class Page(HTMLParser):
    """A page's links, pictures, scripts, style sheets, table rows and visible text."""

    def __init__(self, path: Path) -> None:
        super().__init__()
        self.refs: list[str] = []
        self.rows: list[dict] = []
        self.scripts: list[dict] = []
        self.text: list[str] = []
        self.feed(path.read_text(encoding="utf-8"))

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for key in ("href", "src"):
            if a.get(key):
                self.refs.append(a[key])
        if tag == "tr" and "data-status" in a:
            self.rows.append(a)
        if tag == "script":
            self.scripts.append(a)

    def handle_data(self, data):
        self.text.append(data)


def local_target(page: Path, ref: str) -> Path:
    """The file a relative reference of ``page`` names (it must be relative)."""
    parts = urlsplit(ref)
    assert not parts.scheme and not parts.netloc and not ref.startswith("/"), ref
    return (page.parent / unquote(parts.path)).resolve()


def assert_links_resolve(page: Path) -> Page:
    parsed = Page(page)
    assert parsed.refs, page
    for ref in parsed.refs:
        assert local_target(page, ref).is_file(), f"{page}: {ref} resolves to nothing"
    return parsed


@pytest.fixture
def garments(tmp_path) -> Path:
    """Three generated garments and a broken file; the sleeve's panel is named in markup and
    the skirt's file name holds HTML's special characters."""
    cat = tmp_path / "cat"
    cat.mkdir()
    write_garment(cat / "a_sleeve.obj", lantern_sleeve(n_around=12, n_sleeve=6, n_cuff=2))
    text = (cat / "a_sleeve.obj").read_text().replace("g sleeve\n", f"g {MARKUP}\n")
    (cat / "a_sleeve.obj").write_text(text)
    write_garment(cat / "b_tube.obj", cylinder(circumference=40.0, n_around=16, n_along=6))
    (cat / "c_bad.obj").write_text("this is not a garment\n")
    write_garment(cat / "d_<b>&\"skirt'.obj", cone_skirt(n_around=16, n_along=6))
    return cat


@pytest.fixture
def recipe(tmp_path) -> Path:
    p = tmp_path / "wider.yaml"
    p.write_text(WIDER)
    return p


def test_shown_values_and_links():
    assert shown_number(None) == "-" and shown_number(0.2, "percent") == "20 %"
    assert shown_number(3, "int") == "3" and shown_number(1.23456) == "1.235"
    assert shown({"a": [1.0, 2.5], "b": True, "c": None}) == "a: [1, 2.5]; b: yes; c: -"
    assert shown("x" * 500, limit=10) == "x" * 9 + "\u2026"
    assert link("a #1?%", "index.html") == "a%20%231%3F%25/index.html"
    assert link("<b>&") == "%3Cb%3E%26"


def test_a_garment_folder_never_takes_the_catalogues_names(tmp_path):
    names = output_names(["x/index.html.obj", "y/_catalogue.obj", "z/a.obj"])
    assert names[0][0] == "index.html-2" and names[1][0] == "_catalogue-2"
    assert names[2] == ("a", None)
    (tmp_path / "g.obj").write_text("v 0 0 0\n")
    manifest = tmp_path / "m.csv"
    manifest.write_text("garment,name\ng.obj,_catalogue\n")
    with pytest.raises(PtailorError, match="catalogue's"):
        read_manifest(manifest, check=lambda column, text: text)


@pytest.mark.slow
def test_batch_html_shows_every_garment_its_status_reason_and_gates(tmp_path, garments, recipe):
    out, log = tmp_path / "out", tmp_path / "log.jsonl"
    r = run("batch", recipe, garments, "-o", out, "-j", "1", "--html", "--log", log, *GATES)
    assert r.exit_code == 1, r.output
    assert f"catalogue: {out / 'index.html'}" in r.stderr
    recs = read_log(log)
    assert [x["status"] for x in recs] == ["failed", "ok", "failed", "failed"]
    assert recs[0]["failed_gates"] == ["--max-boundary-deviation"]
    assert recs[3]["failed_gates"] == ["--max-area-change", "--max-boundary-deviation"]
    assert recs[1]["failed_gates"] is None and recs[2]["failure"] == "input"

    page = assert_links_resolve(out / "index.html")
    assert [row["data-status"] for row in page.rows] == ["failed", "ok", "failed", "failed"]
    assert page.rows[3]["data-gates"] == "--max-area-change --max-boundary-deviation"
    text = " ".join(page.text)
    assert "not an OBJ" in text and "area change 22.3 % > 21 %" in text
    assert "d_<b>&\"skirt'" in text  # the file name, shown as text
    raw = (out / "index.html").read_text()
    assert "d_<b>" not in raw and "d_&lt;b&gt;&amp;&#34;skirt&#39;" in raw
    assert [s["src"] for s in page.scripts] == [f"{CATALOGUE_DIR}/catalogue.js"]
    # the tube (ok) has a page, its thumbnail, both in its folder's marker
    tube = out / "b_tube"
    assert {"index.html", "thumbnail.png"} <= set(read_marker(tube))
    garment = assert_links_resolve(tube / "index.html")
    assert "pattern.svg" in garment.refs and "../index.html" in garment.refs
    assert "report.json" in garment.refs and "pattern.dxf" in garment.refs
    check_output_dir(tube)  # a later run may replace the folder whole
    # what the gates rejected is kept for review, not as the garment's folder
    assert not (out / "a_sleeve").exists()
    rejected = out / "_rejected" / "a_sleeve"
    assert {"pattern.svg", "report.json", "index.html", "thumbnail.png"} <= set(
        read_marker(rejected)
    )
    assert page.rows[0]["data-status"] == "failed"
    assert "_rejected/a_sleeve/index.html" in page.refs
    assert "_rejected/d_%3Cb%3E%26%22skirt%27/index.html" in page.refs
    kept = assert_links_resolve(rejected / "index.html")
    assert "../../index.html" in kept.refs and "../../_catalogue/catalogue.css" in kept.refs
    assert "Rejected by the quality gates" in " ".join(kept.text)
    assert json.loads((rejected / "report.json").read_text())["panels"]


@pytest.mark.slow
def test_garment_page_tables_steps_and_escaped_panel_names(tmp_path, garments):
    recipe = tmp_path / "markup.yaml"  # a region named in markup: the recipe shows it too
    recipe.write_text(
        "steps: [{op: scale, region: {panels: ['" + MARKUP + "']}, direction: around, "
        "axis: auto, factor: 1.2}]\n"
    )
    out = tmp_path / "out"
    r = run("batch", recipe, garments / "a_sleeve.obj", "-o", out, "-j", "1", "--html")
    assert r.exit_code == 0, r.output
    index = (out / "index.html").read_text()
    assert MARKUP not in index and "&lt;script&gt;alert(1)&lt;/script&gt;" in index
    assert MARKUP in " ".join(Page(out / "index.html").text)  # the recipe, as text
    page_path = out / "a_sleeve" / "index.html"
    raw = page_path.read_text()
    assert MARKUP not in raw and "&lt;script&gt;alert(1)&lt;/script&gt;" in raw
    page = Page(page_path)
    text = " ".join(page.text)
    assert MARKUP in text and "cuff" in text  # the panel table, names as text
    assert "scale" in text and "factor" in text  # the step
    report = json.loads((out / "a_sleeve" / "report.json").read_text())
    for seam in report["seams"]:
        assert seam["name"] in text
    assert page.scripts == []  # a garment page needs no script


@pytest.mark.slow
def test_rerun_keeps_every_row_and_the_folder_can_move(tmp_path, garments, recipe):
    out = tmp_path / "out"
    run("batch", recipe, garments, "-o", out, "-j", "1", "--html", *GATES)
    thumb = out / "b_tube" / "thumbnail.png"
    made = thumb.stat().st_mtime_ns
    r = run("batch", recipe, garments, "-o", out, "-j", "1", "--html", *GATES)
    assert r.exit_code == 1
    rows = Page(out / "index.html").rows
    assert [row["data-status"] for row in rows] == ["failed", "skipped", "failed", "failed"]
    assert thumb.stat().st_mtime_ns == made  # written once
    # --force replaces the folders whole (the page and thumbnail are the marker's)
    r = run("batch", recipe, garments, "-o", out, "-j", "1", "--html", "--force", *GATES)
    assert r.exit_code == 1 and "output folder holds" not in r.output
    assert [row["data-status"] for row in Page(out / "index.html").rows][1] == "ok"
    # without the gates the rejected garments pass: what was kept of them goes (and the
    # catalogue is kept current without --html: OUT has one)
    assert (out / "_rejected" / "a_sleeve").is_dir()
    r = run("batch", recipe, garments, "-o", out, "-j", "1")
    assert f"catalogue: {out / 'index.html'}" in r.stderr
    assert [row["data-status"] for row in Page(out / "index.html").rows] == [
        "ok", "skipped", "failed", "ok"
    ]  # fmt: skip
    assert not (out / "_rejected").exists() and (out / "a_sleeve" / "index.html").is_file()
    moved = tmp_path / "elsewhere" / "catalogue"
    shutil.move(str(out), str(moved))
    assert_links_resolve(moved / "index.html")
    assert_links_resolve(moved / "b_tube" / "index.html")


@pytest.mark.slow
def test_report_command_rebuilds_from_saved_records_log_or_folders(tmp_path, garments, recipe):
    out, log = tmp_path / "out", tmp_path / "log.jsonl"
    run("batch", recipe, garments, "-o", out, "-j", "1", "--log", log, *GATES)
    assert not (out / "index.html").exists()  # no --html, no page
    r = run("report", out)  # no records saved: the folders alone
    assert r.exit_code == 0, r.output
    assert r.stdout.strip() == str(out / "index.html")
    rows = Page(out / "index.html").rows
    assert [row["data-status"] for row in rows] == ["earlier"]
    r = run("report", out, "--log", log)  # the log: every garment
    assert r.exit_code == 0, r.output
    assert [row["data-status"] for row in Page(out / "index.html").rows] == [
        "failed", "ok", "failed", "failed"
    ]  # fmt: skip
    (out / "index.html").unlink()
    r = run("report", out)  # the records the last catalogue saved (the log's)
    assert r.exit_code == 0, r.output
    statuses = [row["data-status"] for row in Page(out / "index.html").rows]
    assert statuses == ["failed", "ok", "failed", "failed"]
    # a garment folder from another run is shown too, as earlier
    run("batch", recipe, garments / "b_tube.obj", "-o", tmp_path / "o2", "-j", "1")
    shutil.copytree(tmp_path / "o2" / "b_tube", out / "tube_copy")
    run("report", out)
    rows = Page(out / "index.html").rows
    assert [row["data-status"] for row in rows][-1] == "earlier"


def test_report_refuses_what_is_not_a_batch_output(tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    r = run("report", empty)
    assert r.exit_code == 2 and "not a batch output root" in r.stderr and str(empty) in r.stderr
    assert list(empty.iterdir()) == []
    r = run("report", tmp_path / "missing")
    assert r.exit_code == 2
    bad_log = tmp_path / "log.jsonl"
    bad_log.write_text('{"not": "a record"}\n')
    r = run("report", empty, "--log", bad_log)
    assert r.exit_code == 2 and "line 1 is not a ptailor batch record" in r.stderr
    assert list(empty.iterdir()) == []


@pytest.mark.slow
def test_a_foreign_index_html_is_never_replaced(tmp_path, garments, recipe):
    out = tmp_path / "out"
    out.mkdir()
    mine = out / "index.html"
    mine.write_text("<html>my own page</html>\n")
    r = run("batch", recipe, garments / "b_tube.obj", "-o", out, "-j", "1", "--html")
    assert r.exit_code == 2 and "not a ptailor catalogue page" in r.stderr
    assert sorted(p.name for p in out.iterdir()) == ["index.html"]  # nothing ran
    run("batch", recipe, garments / "b_tube.obj", "-o", out, "-j", "1")
    r = run("report", out)
    assert r.exit_code == 2 and str(mine) in r.stderr
    assert mine.read_text() == "<html>my own page</html>\n"
    assert "index.html" not in read_marker(out / "b_tube")  # no garment page either


def test_catalogue_rows_from_records_without_folders(tmp_path):
    recs = [
        {"index": 1, "garment": "g/a.obj", "out": "OUT/a", "status": "failed",
         "failure": "timeout", "reason": "timeout: not done in 5 s (--timeout)"},
        {"index": 2, "garment": "g/b.obj", "out": "OUT/b", "status": "interrupted"},
    ]  # fmt: skip
    rows = catalogue_rows(tmp_path, recs)
    assert [(r.name, r.status, r.folder) for r in rows] == [
        ("a", "failed", None), ("b", "interrupted", None)
    ]  # fmt: skip
    page = write_catalogue(tmp_path, recs, Summary(seconds=2.0, ran=1, where="in-process"))
    text = " ".join(Page(page).text)
    assert "30.0 garments/min" in text and "timeout: not done in 5 s" in text
    assert (tmp_path / CATALOGUE_DIR / MARKER).is_file()


def _png(path: Path, size=(400, 300)) -> None:
    from PIL import Image

    Image.new("RGB", size, (250, 250, 200)).save(path)


def test_a_redraped_garment_shows_its_check_and_its_columns(tmp_path):
    """A report with the re-drape check: its picture and table on the garment page, its
    numbers as columns of the index (absent for a batch without it)."""
    from ptailor.batch import RECORD_KEYS, key_numbers
    from ptailor.run.folder import staged_dir

    report = {
        "units": {"computation": "cm"},
        "panels": [{"name": "front", "area_before": 10.0, "area_after": 11.0,
                    "intrinsic_scale_error": {"mean": 0.0, "p95": 0.01, "max": 0.02},
                    "flipped_triangles": 0},
                   {"name": "back", "area_before": 10.0, "area_after": 10.5,
                    "intrinsic_scale_error": {"mean": 0.0, "p95": 0.03, "max": 0.05},
                    "flipped_triangles": 0}],
        "seams": [{"name": "side", "panels": ["front", "back"], "mismatch": -0.25}],
        "steps": [{"op": "shorten", "opening": "hem", "by": 5,
                   "achieved": {"3d": {"mean": 4.99, "min": 4.9, "max": 5.1}}}],
        "verify": {"engine": "newton", "device": "cpu", "settled": True,
                   "ours": {"panels": {"front": {"stretch": {"p95": 1.031},
                                                 "displacement": {"p95": 0.42}}}},
                   "baseline": {"panels": {"front": {"stretch": {"p95": 1.2},
                                                     "displacement": {"p95": 0.9}}}}},
        "warnings": ["a warning <i>in markup</i>"],
        "outputs": ["preview.png", "report.json", "verify.png"],
    }  # fmt: skip
    with staged_dir(tmp_path / "g") as tmp:
        (tmp / "report.json").write_text(json.dumps(report))
        _png(tmp / "preview.png")
        _png(tmp / "verify.png")
    rec = dict.fromkeys(RECORD_KEYS)
    rec.update(index=1, garment="g.obj", out="OUT/g", status="ok", **key_numbers(report))
    page = write_catalogue(tmp_path, [rec], Summary())
    index = Page(page)
    assert "re-drape stretch p95" in index.text and "1.031" in index.text
    garment = assert_links_resolve(tmp_path / "g" / "index.html")
    text = " ".join(garment.text)
    assert "verify.png" in garment.refs and "Re-drape check" in text
    assert "1.031" in text and "1.2" in text and "0.42" in text
    assert "achieved: 3d: mean: 4.99; min: 4.9; max: 5.1" in text
    assert "a warning <i>in markup</i>" in text  # as text
    raw = (tmp_path / "g" / "index.html").read_text()
    assert '<tr class="worst" title="the largest intrinsic-scale error p95"><td>back' in raw
    assert '<tr class="worst" title="the largest seam mismatch"><td>side' in raw
    from PIL import Image

    with Image.open(tmp_path / "g" / "thumbnail.png") as im:
        assert max(im.size) <= 360 and im.size[0] / im.size[1] == pytest.approx(4 / 3, rel=0.02)
    # without the check, no such column
    rec2 = dict(rec, verify_stretch_p95=None, verify_displacement_p95=None)
    assert "re-drape stretch p95" not in Page(write_catalogue(tmp_path, [rec2])).text


@pytest.mark.slow
def test_a_batch_without_pictures_still_has_its_pages(tmp_path, garments, recipe):
    """``--formats obj``: no SVG, no preview, so no thumbnail: the pages say so."""
    out = tmp_path / "out"
    args = ("--formats", "obj", "--no-baseline", "--html")
    r = run("batch", recipe, garments / "b_tube.obj", "-o", out, "-j", "1", *args)
    assert r.exit_code == 0, r.output
    index = assert_links_resolve(out / "index.html")
    assert "no preview" in index.text
    page = assert_links_resolve(out / "b_tube" / "index.html")
    assert "No pattern picture was written (--formats)." in page.text
    assert not (out / "b_tube" / "thumbnail.png").exists()
    assert "-" in Page(out / "b_tube" / "index.html").text  # no baseline: its column empty


@pytest.mark.slow
def test_names_a_url_would_misread_still_link(tmp_path, recipe):
    """``#``, ``?``, spaces and non-ASCII letters in a garment's name: quoted links that
    resolve, on the index and on the garment's page."""
    cat = tmp_path / "cat"
    cat.mkdir()
    write_garment(cat / "manche #1? évasée 中.obj", cylinder(n_around=12, n_along=4))
    out = tmp_path / "out"
    r = run("batch", recipe, cat, "-o", out, "-j", "1", "--html")
    assert r.exit_code == 0, r.output
    index = assert_links_resolve(out / "index.html")
    assert "manche%20%231%3F%20%C3%A9vas%C3%A9e%20%E4%B8%AD/index.html" in index.refs
    assert_links_resolve(out / "manche #1? évasée 中" / "index.html")
