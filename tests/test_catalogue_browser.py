"""The catalogue in a real browser: headless Chromium through selenium.

Every row there, sorting by a column reorders the rows, a filter hides the others, every
picture loads and every link resolves, a name in markup shows as text (no script of it
runs), and the console has no error. Screenshots of the index and a garment page are
written under the test's temporary folder for a person to look at (their paths are
printed: ``pytest -s``).

Needs Debian's ``chromium`` and ``chromium-driver`` (``.ci/run`` installs them where it
may) and selenium (the test extra); skips, saying which is missing, elsewhere.
"""

from __future__ import annotations

import shutil
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest
from click.testing import CliRunner

from ptailor.cli.main import cli
from ptailor.formats.obj import write_garment
from ptailor.samples import cone_skirt, cylinder, lantern_sleeve

WIDER = "steps: [{op: scale, region: all, direction: around, axis: auto, factor: 1.2}]\n"
GATES = ("--max-area-change", "0.21", "--max-boundary-deviation", "2.0")
MARKUP = "<script>alert(1)</script>"
#: where Debian puts them
CHROMIUM = ("/usr/bin/chromium", "/usr/bin/chromium-browser")
CHROMEDRIVER = ("/usr/bin/chromedriver",)

pytestmark = pytest.mark.slow


def _first(paths: tuple[str, ...], name: str) -> str | None:
    found = [p for p in paths if Path(p).is_file()]
    return found[0] if found else shutil.which(name)


@pytest.fixture(scope="module")
def browser():
    webdriver = pytest.importorskip(
        "selenium.webdriver", reason="selenium is not installed (pip install '.[test]')"
    )
    from selenium.webdriver.chrome.service import Service

    chromium, driver = _first(CHROMIUM, "chromium"), _first(CHROMEDRIVER, "chromedriver")
    if chromium is None or driver is None:
        pytest.skip(
            "no Chromium here: apt-get install chromium chromium-driver (.ci/run does where "
            "it runs as root)"
        )
    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    for arg in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage",
                "--disable-gpu", "--window-size=1400,1000"):  # fmt: skip
        options.add_argument(arg)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    d = webdriver.Chrome(service=Service(executable_path=driver), options=options)
    d.set_page_load_timeout(60)
    yield d
    d.quit()


@pytest.fixture(scope="module")
def batch_out(tmp_path_factory) -> Path:
    """A batch with the catalogue: a garment per status, gates failing two, a broken file,
    a panel named in markup and a file name with HTML's special characters."""
    root = tmp_path_factory.mktemp("catalogue")
    cat = root / "cat"
    cat.mkdir()
    write_garment(cat / "a_sleeve.obj", lantern_sleeve(n_around=12, n_sleeve=6, n_cuff=2))
    write_garment(cat / "b_tube.obj", cylinder(circumference=40.0, n_around=16, n_along=6))
    (cat / "c_bad.obj").write_text("this is not a garment\n")
    write_garment(cat / "d_<b>&\"skirt'.obj", cone_skirt(n_around=16, n_along=6))
    write_garment(cat / "e_sleeve.obj", lantern_sleeve(circumference=26.0, n_around=10))
    text = (cat / "e_sleeve.obj").read_text().replace("g sleeve\n", f"g {MARKUP}\n")
    (cat / "e_sleeve.obj").write_text(text)
    recipe = root / "wider.yaml"
    recipe.write_text(WIDER)
    out = root / "out"
    args = ["batch", recipe, cat, "-o", out, "-j", "1", "--html", *GATES]
    r = CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)
    assert r.exit_code == 1, r.output
    return out


def _open(browser, page: Path) -> None:
    browser.get(page.as_uri())
    browser.get_log("browser")  # (what a page before it logged)
    browser.get(page.as_uri())


def _rows(browser) -> list:
    return browser.find_elements("css selector", "#catalogue tbody tr")


def _statuses(browser, visible_only: bool = False) -> list[str]:
    return [
        r.get_attribute("data-status")
        for r in _rows(browser)
        if not visible_only or r.is_displayed()
    ]


def _column(browser, label: str) -> int:
    heads = browser.find_elements("css selector", "#catalogue thead th")
    return [h.text.strip(" \u25b2\u25bc") for h in heads].index(label)


def _sort_values(browser, col: int) -> list[str]:
    return [
        r.find_elements("css selector", "td")[col].get_attribute("data-sort")
        for r in _rows(browser)
    ]


def _click_heading(browser, label: str) -> None:
    col = _column(browser, label)
    browser.find_elements("css selector", "#catalogue thead th")[col].find_element(
        "css selector", "button"
    ).click()


def _no_console_errors(browser) -> None:
    severe = [e for e in browser.get_log("browser") if e.get("level") == "SEVERE"]
    assert severe == [], severe


def _check_pictures_and_links(browser, page: Path) -> None:
    for img in browser.find_elements("css selector", "img"):
        ok = browser.execute_script(
            "return arguments[0].complete && arguments[0].naturalWidth > 0;", img
        )
        assert ok, f"{page}: {img.get_attribute('src')} did not load"
    for a in browser.find_elements("css selector", "a[href]"):
        href = a.get_attribute("href")  # resolved by the browser
        parts = urlsplit(href)
        assert parts.scheme == "file", href
        assert Path(unquote(parts.path)).is_file(), f"{page}: {href} resolves to nothing"
        root = next(q for q in page.parents if (q / "_catalogue").is_dir())  # the batch's
        assert Path(unquote(parts.path)).resolve().is_relative_to(root.resolve())


def test_the_catalogue_page_in_chromium(browser, batch_out, tmp_path):
    page = batch_out / "index.html"
    _open(browser, page)
    assert _statuses(browser) == ["failed", "ok", "failed", "failed", "failed"]
    assert browser.find_element("id", "controls").is_displayed()  # the script ran
    _check_pictures_and_links(browser, page)
    # the tube's, and the three the gates rejected (kept for review)
    assert len(browser.find_elements("css selector", "td.thumb img")) == 4
    names = [e.text for e in browser.find_elements("css selector", "td.garment .name")]
    assert "d_<b>&\"skirt'" in names  # HTML's special characters shown as text

    _click_heading(browser, "status")  # failed first
    statuses = _statuses(browser)
    assert statuses[:4] == ["failed"] * 4 and statuses[-1] == "ok"
    _click_heading(browser, "area change")
    col = _column(browser, "area change")
    values = _sort_values(browser, col)
    numbers = [float(v) for v in values if v]
    assert numbers == sorted(numbers) and values[-1] == ""  # no value last
    _click_heading(browser, "area change")  # again: reversed, no value still last
    values = _sort_values(browser, col)
    numbers = [float(v) for v in values if v]
    assert numbers == sorted(numbers, reverse=True) and values[-1] == ""
    _click_heading(browser, "#")  # back to the input order
    assert _sort_values(browser, 0) == ["1", "2", "3", "4", "5"]

    from selenium.webdriver.support.ui import Select

    Select(browser.find_element("id", "filter-status")).select_by_value("ok")
    assert _statuses(browser, visible_only=True) == ["ok"]
    assert browser.find_element("id", "shown-count").text == "1 of 5 garments shown"
    Select(browser.find_element("id", "filter-status")).select_by_value("")
    Select(browser.find_element("id", "filter-gate")).select_by_value("--max-area-change")
    shown = [r for r in _rows(browser) if r.is_displayed()]
    assert len(shown) == 1 and "skirt" in shown[0].text
    Select(browser.find_element("id", "filter-gate")).select_by_value("--max-boundary-deviation")
    assert len([r for r in _rows(browser) if r.is_displayed()]) == 3
    Select(browser.find_element("id", "filter-gate")).select_by_value("")
    assert len([r for r in _rows(browser) if r.is_displayed()]) == 5
    box = browser.find_element("id", "filter-name")
    box.send_keys("SLEEVE")  # a part of the name, any case
    assert [r.get_attribute("data-status") for r in _rows(browser) if r.is_displayed()] == [
        "failed", "failed"
    ]  # fmt: skip
    box.clear()
    box.send_keys("x")  # (clear() fires no input event: type again)
    box.send_keys("\b")
    assert len([r for r in _rows(browser) if r.is_displayed()]) == 5
    _no_console_errors(browser)
    shot = tmp_path / "catalogue.png"
    browser.save_screenshot(str(shot))
    print(f"\ncatalogue screenshot: {shot}")


def test_a_garment_page_in_chromium(browser, batch_out, tmp_path):
    page = batch_out / "b_tube" / "index.html"
    _open(browser, page)
    _check_pictures_and_links(browser, page)
    assert (
        browser.find_element("css selector", "img.pattern")
        .get_attribute("src")
        .endswith("pattern.svg")
    )
    tables = browser.find_elements("css selector", "table.data")
    assert len(tables) == 3  # panels, seams and the points of measure before and after
    assert "tube" in tables[0].text
    assert "waist" in tables[2].text and "hem" in tables[2].text
    _no_console_errors(browser)
    browser.find_element("id", "back").click()
    assert browser.current_url == (batch_out / "index.html").as_uri()
    shot = tmp_path / "garment.png"
    browser.save_screenshot(str(shot))
    print(f"\ngarment page screenshot: {shot}")


def test_a_name_in_markup_shows_as_text_in_chromium(browser, tmp_path_factory):
    """A panel named ``<script>...`` (from the OBJ's group): text on the page, no alert."""
    root = tmp_path_factory.mktemp("markup")
    g = root / "sleeve.obj"
    write_garment(g, lantern_sleeve(n_around=12, n_sleeve=6, n_cuff=2))
    g.write_text(g.read_text().replace("g sleeve\n", f"g {MARKUP}\n"))
    recipe = root / "wider.yaml"
    recipe.write_text(WIDER)
    out = root / "out"
    args = ["batch", recipe, g, "-o", out, "-j", "1", "--html"]
    assert CliRunner().invoke(cli, [str(a) for a in args]).exit_code == 0
    page = out / "sleeve" / "index.html"
    _open(browser, page)  # an alert would make selenium raise here and below
    cells = [c.text for c in browser.find_elements("css selector", "#panels td:first-child")]
    assert MARKUP in cells
    assert browser.find_elements("css selector", "body script") == []
    _no_console_errors(browser)


# --------------------------------------------------------------------------- real garments


@pytest.fixture(scope="module")
def shared_out(tmp_path_factory) -> Path:
    """The four shared garments shortened at the hem, each in its own units (a manifest),
    with a gate that fails one: tee6's hem panels change area by 11.4 %, the others' by
    8-9.6 %."""
    from tests.conftest import GARMENTS

    if not (GARMENTS / "gpg_tee6" / "tee6_sim.obj").is_file():
        pytest.skip(f"{GARMENTS} not available (../shared is absent)")
    root = tmp_path_factory.mktemp("shared")
    manifest = root / "garments.csv"
    manifest.write_text(
        "garment,pattern_units,drape_units\n"
        f"{GARMENTS}/diffavatar/tshirt.obj,auto,\n"
        f"{GARMENTS}/gpg_tee6/tee6_sim.obj,0.3333cm,0.3333cm\n"
        f"{GARMENTS}/diffavatar/longsleeve_initial.obj,auto,\n"
        f"{GARMENTS}/diffavatar/dress_initial.obj,auto,\n"
    )
    from ptailor.recipe.bundled import bundled_recipe

    recipe = root / "shorter-hem.yaml"
    recipe.write_text(bundled_recipe("shorter-hem"))
    out = root / "out"
    args = ["batch", recipe, "--manifest", manifest, "-o", out,
            "-j", "2", "--html", "--max-area-change", "0.1"]  # fmt: skip
    r = CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)
    assert r.exit_code == 1, r.output
    return out


def test_the_shared_garments_catalogue(shared_out):
    """Every garment, the failed one's reason, each garment page with its SVG and tables."""
    from tests.test_catalogue import Page, assert_links_resolve

    page = assert_links_resolve(shared_out / "index.html")
    assert [r["data-status"] for r in page.rows] == ["ok", "failed", "ok", "ok"]
    assert page.rows[1]["data-gates"] == "--max-area-change"
    text = " ".join(page.text)
    assert "gate: " in text and "> 10 %" in text
    for name in ("tshirt", "longsleeve_initial", "dress_initial"):
        garment = assert_links_resolve(shared_out / name / "index.html")
        assert "pattern.svg" in garment.refs
        report = __import__("json").loads((shared_out / name / "report.json").read_text())
        shown = " ".join(Page(shared_out / name / "index.html").text)
        assert all(p["name"] in shown for p in report["panels"])
        assert all(s["name"] in shown for s in report["seams"])
        assert "shorten" in shown and "achieved" in shown
    assert not (shared_out / "tee6_sim").exists()  # a gate's failure writes no folder,
    kept = assert_links_resolve(shared_out / "_rejected" / "tee6_sim" / "index.html")
    assert "pattern.svg" in kept.refs  # but what it rejected is kept for review


def test_the_shared_garments_catalogue_sorted_in_chromium(browser, shared_out, tmp_path):
    _open(browser, shared_out / "index.html")
    _click_heading(browser, "status")
    assert _statuses(browser) == ["failed", "ok", "ok", "ok"]
    first = _rows(browser)[0].text
    assert "tee6_sim" in first and "area change" in first
    _check_pictures_and_links(browser, shared_out / "index.html")
    assert len(browser.find_elements("css selector", "td.thumb img")) == 4
    _no_console_errors(browser)
    _rows(browser)[0].find_element("css selector", "a.name").click()  # the rejected tee
    assert browser.current_url == (shared_out / "_rejected/tee6_sim/index.html").as_uri()
    assert "Rejected by the quality gates" in browser.find_element("tag name", "body").text
    for name in ("_rejected/tee6_sim", "tshirt", "dress_initial"):
        _open(browser, shared_out / name / "index.html")
        _check_pictures_and_links(browser, shared_out / name / "index.html")
        _no_console_errors(browser)
    shot = tmp_path / "shared.png"
    browser.save_screenshot(str(shot))
    print(f"\nshared catalogue screenshot: {shot}")
