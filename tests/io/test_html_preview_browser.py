"""The HTML preview in a real headless browser (Chromium driven by Selenium).

Marked ``browser``: skipped, with the reason, when Selenium, Chromium or its driver is missing
(``apt-get install chromium chromium-driver``; ``.ci/run`` installs them and sets
``TRCOPT_REQUIRE_BROWSER=1``, which turns the skip into a failure). The browser and driver can be
named with ``TRCOPT_CHROMIUM`` and ``TRCOPT_CHROMEDRIVER``.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

from trcopt.cli import main
from trcopt.pipeline import PlanOptions, plan_file

pytestmark = pytest.mark.browser

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = ROOT / "problems" / "siemens" / "ex06_bottleneck_cdon.mpf"  # 8 programmed, 7 tool-centre segments


def _find(env: str, *names: str) -> str | None:
    given = os.environ.get(env)
    if given:
        return given if Path(given).exists() else None
    return next((p for p in map(shutil.which, names) if p), None)


def _unavailable(reason: str) -> None:
    """Skip, or fail where the browser is required (``TRCOPT_REQUIRE_BROWSER=1``, set by ``.ci/run``)."""
    if os.environ.get("TRCOPT_REQUIRE_BROWSER") == "1":
        pytest.fail(f"TRCOPT_REQUIRE_BROWSER=1 but {reason}")
    pytest.skip(reason)


@pytest.fixture(scope="module")
def browser():
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        _unavailable("selenium is not installed (pip install selenium, or the test extra)")
    binary = _find("TRCOPT_CHROMIUM", "chromium", "chromium-browser", "google-chrome")
    driver_path = _find("TRCOPT_CHROMEDRIVER", "chromedriver")
    if not binary or not driver_path:
        _unavailable("no headless browser: install Chromium and its driver (apt-get install chromium chromium-driver)")
    opts = webdriver.ChromeOptions()
    opts.binary_location = binary
    flags = ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1280,1000")
    for arg in flags:
        opts.add_argument(arg)
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(driver_path), options=opts)
    driver.set_page_load_timeout(20)
    yield driver
    driver.quit()


@pytest.fixture(scope="module")
def golden(tmp_path_factory):
    out = tmp_path_factory.mktemp("html") / "ex06.html"
    assert main(["plan", str(GOLDEN), "-q", "--html", str(out)]) == 0
    return out, plan_file(GOLDEN, PlanOptions())


@pytest.fixture
def page(browser, golden):
    out, result = golden
    browser.get(out.as_uri())
    assert browser.execute_script("return document.body.dataset.ready") == "1"
    return browser, result


def _errors(driver) -> list[dict]:
    return [e for e in driver.get_log("browser") if e["level"] in ("SEVERE", "ERROR")]


def _hover_segment(driver, kind: str, index: int, at: float = 0.3):
    """Moves the mouse onto the path element (``seg``/``prog-hit`` number ``index``), ``at`` its length."""
    from selenium.webdriver.common.action_chains import ActionChains

    view = driver.find_element("id", "view")
    x, y, w, h = driver.execute_script(
        "var p = document.querySelectorAll('#view path.' + arguments[0])[arguments[1]];"  # seg or prog-hit
        "var q = p.getPointAtLength(p.getTotalLength() * arguments[2]), r = arguments[3].getBoundingClientRect();"
        "return [q.x, q.y, r.width, r.height];",
        kind, index, at, view,
    )
    ActionChains(driver).move_to_element_with_offset(view, round(x - w / 2), round(y - h / 2)).perform()


def _tip(driver) -> dict:
    return driver.execute_script(
        "var t = document.getElementById('tip'); return {hidden: t.hidden, text: t.textContent,"
        " block: t.dataset.block, line: t.dataset.line, kind: t.dataset.kind};"
    )


def test_loads_without_console_errors_and_draws_every_segment(page) -> None:
    driver, result = page
    assert _errors(driver) == []
    count = driver.execute_script
    assert count("return document.querySelectorAll('#view path.seg').length") == len(result.toolpath) == 7
    assert count("return document.querySelectorAll('#view path.prog').length") == len(result.programmed) == 8
    tools = sum(s.radius > 0 for s in result.toolpath) + (result.toolpath[0].radius > 0)  # junctions + start
    assert count("return document.querySelectorAll('#view path.tool').length") == tools == 6
    # the rapid is dashed, the two omitted blocks (10763) are marked, highlighted and listed with links
    assert count("return document.querySelector('#view path.seg[data-rapid=\"1\"]').getAttribute('stroke-dasharray')")
    assert count("return document.querySelectorAll('#view g.mark').length") == 2
    assert count("return document.querySelectorAll('#view path.omitted').length") == 2
    links = driver.find_elements("css selector", "#diags a")
    assert [a.get_attribute("href").rsplit("#", 1)[1] for a in links] == ["mark-0", "mark-1"]
    assert "10763 (N50)" in links[0].text
    # axes with a mm scale, the start, arrows, the speed colouring and its legend
    assert count("return document.querySelector('#layer-axis .axis-name').textContent") == "X [mm]"
    assert count("return document.getElementById('scale-label').textContent").endswith(" mm")
    assert count("return document.getElementById('start').getAttribute('transform')").startswith("translate(")
    assert count("return document.querySelector('path.arrows').getAttribute('d').split('Z').length - 1") >= 5
    assert count("return document.querySelectorAll('#layer-speed path').length") >= 6
    assert count("return document.getElementById('speed-scale') !== null")
    # the log is really read: an error the page reports shows up
    driver.execute_script("console.error('probe from the test')")
    assert any("probe from the test" in e["message"] for e in _errors(driver))


def test_switching_views(page) -> None:
    driver, _ = page

    def toolpath_box() -> tuple[float, float]:
        script = "var b = document.getElementById('layer-tp').getBBox(); return [b.width, b.height];"
        return driver.execute_script(script)

    w_xy, h_xy = toolpath_box()
    assert w_xy > 300 and h_xy > 50
    driver.find_element("css selector", "button[data-view='xz']").click()
    assert driver.execute_script("return document.getElementById('view').dataset.view") == "xz"
    assert driver.find_element("css selector", "button[data-view='xz']").get_attribute("class") == "view on"
    names = driver.execute_script(
        "return Array.from(document.querySelectorAll('#layer-axis .axis-name')).map(e => e.textContent)"
    )
    assert names == ["X [mm]", "Z [mm]"]
    w_xz, h_xz = toolpath_box()
    assert w_xz > 300 and h_xz < 1.0  # the part lies in Z = 0: seen from the front it is a line
    driver.find_element("css selector", "button[data-view='iso']").click()
    w_iso, h_iso = toolpath_box()
    assert h_iso > 20  # the triad X, Y, Z replaces the grid
    assert driver.execute_script("return document.querySelectorAll('#layer-overlay .axis-name').length") == 3
    driver.find_element("css selector", "button[data-view='xy']").click()
    assert toolpath_box() == pytest.approx((w_xy, h_xy), abs=0.5)
    assert _errors(driver) == []


@pytest.mark.parametrize(("index", "block", "line"), [(2, "N30", "5"), (3, "N40", "6"), (5, "N70", "9")])
def test_hovering_a_segment_shows_its_block(page, index: int, block: str, line: str) -> None:
    driver, result = page
    assert result.toolpath[index].span.block == block
    _hover_segment(driver, "seg", index)
    tip = _tip(driver)
    assert not tip["hidden"] and tip["kind"] == "toolpath"
    assert (tip["block"], tip["line"]) == (block, line)
    assert tip["text"].startswith(block) and f"line {line}" in tip["text"] and "mm/min" in tip["text"]
    # the segment is highlighted, and so is its time interval in the speed plot
    classes = driver.execute_script(f"return document.querySelectorAll('#view path.seg')[{index}].className.baseVal")
    assert "hl" in classes
    x0 = driver.execute_script("return +document.getElementById('plot-hl').getAttribute('x')")
    assert driver.execute_script("return document.getElementById('plot-hl').getAttribute('visibility')") == "visible"
    timed = result.timing.segments_with_times()[index]
    width = driver.execute_script("return document.getElementById('plot').getBoundingClientRect().width")
    x_of = lambda t: 60 + (width - 60 - 14) * t / result.timing.duration  # noqa: E731 (the plot's margins)
    assert x0 == pytest.approx(x_of(timed.t_start_s), abs=0.5)
    shaded = driver.execute_script("return +document.getElementById('plot-hl').getAttribute('width')")
    assert shaded == pytest.approx(max(1.0, x_of(timed.t_end_s) - x_of(timed.t_start_s)), abs=0.5)


def test_hovering_the_programmed_path_and_the_speed_plot(page) -> None:
    from selenium.webdriver.common.action_chains import ActionChains

    driver, result = page
    _hover_segment(driver, "prog-hit", 4, at=0.8)  # N50, the omitted block: its programmed segment
    tip = _tip(driver)
    assert (tip["kind"], tip["block"]) == ("programmed", "N50")
    # the plot: the middle of N30 in time highlights N30 on the path and puts the cursor there
    timed = result.timing.segments_with_times()[2]
    plot = driver.find_element("id", "plot-hit")
    x, w = driver.execute_script(
        "var r = arguments[0].getBoundingClientRect(); return [r.left, r.width];", plot
    )
    frac = 0.5 * (timed.t_start_s + timed.t_end_s) / result.timing.duration
    ActionChains(driver).move_to_element_with_offset(plot, round(frac * w - w / 2), 0).perform()
    assert driver.execute_script("return document.querySelectorAll('#view path.seg.hl').length") == 1
    assert driver.execute_script("return document.querySelector('#view path.seg.hl').dataset.block") == "N30"
    assert driver.execute_script("return document.getElementById('cursor').getAttribute('visibility')") == "visible"
    assert _tip(driver)["block"] == "N30" and "mm/min" in _tip(driver)["text"]
    cy = driver.execute_script("return +document.getElementById('cursor').getAttribute('cy')")
    seg_y = driver.execute_script(
        "var p = document.querySelectorAll('#view path.seg')[2]; return p.getPointAtLength(0).y"
    )
    assert cy == pytest.approx(seg_y, abs=1.0)  # N30 runs along Y = 5


def test_alarm_links_jump_to_their_place(page) -> None:
    driver, _ = page
    state = "return [window.trcoptPreview.state.W, window.trcoptPreview.state.H]"
    driver.execute_script("window.trcoptPreview.state.tx += 400")  # the marks are off-centre first
    for k in (1, 0):
        driver.find_elements("css selector", "#diags a")[k].click()
        w, h = driver.execute_script(state)
        cx, cy = driver.execute_script(
            f"var c = document.querySelector('#mark-{k} circle'); return [+c.getAttribute('cx'), +c.getAttribute('cy')]"
        )
        assert (cx, cy) == pytest.approx((w / 2, h / 2), abs=1.0)
        assert "flash" in driver.execute_script(f"return document.getElementById('mark-{k}').getAttribute('class')")


def test_wheel_zooms_and_drag_pans(page) -> None:
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.actions.wheel_input import ScrollOrigin

    driver, _ = page
    get = "var s = window.trcoptPreview.state; return [s.scale, s.tx, s.ty];"
    scale0, _, _ = driver.execute_script(get)
    view = driver.find_element("id", "view")
    ActionChains(driver).scroll_from_origin(ScrollOrigin.from_element(view, 0, -150), 0, -200).perform()
    scale1, tx1, ty1 = driver.execute_script(get)
    assert scale1 > 1.2 * scale0
    drag = ActionChains(driver).move_to_element_with_offset(view, 300, -250).click_and_hold()
    drag.move_by_offset(-80, 40).release().perform()
    scale2, tx2, ty2 = driver.execute_script(get)
    assert scale2 == scale1 and (tx2 - tx1, ty2 - ty1) == pytest.approx((-80, 40), abs=1.0)
    assert _errors(driver) == []


def test_pages_without_a_feed_profile_and_without_a_path(browser, tmp_path) -> None:
    from trcopt.io.html_preview import write_html

    too_large = ROOT / "problems" / "heidenhain" / "h02_pocket_r16_too_large.h"
    stopped = tmp_path / "stopped.html"
    assert main(["plan", str(too_large), "-q", "--no-timing", "--html", str(stopped)]) == 1
    browser.get(stopped.as_uri())
    run = browser.execute_script
    assert run("return document.body.dataset.ready") == "1" and _errors(browser) == []
    # coloured by role, no speed plot; the alarm that stopped the program marks the end of the path
    assert run("return document.querySelector('button[data-colour=speed]').disabled")
    assert run("return document.getElementById('plot-box').hidden")
    assert run("return document.querySelector('#view path.seg[data-role=contour]').getAttribute('stroke')") == "#1f5fd6"
    assert run("return document.querySelector('#mark-0 text').textContent").startswith("stopped: error ")
    assert "the program stops here" in browser.find_element("id", "diags").text
    empty = write_html(tmp_path / "empty.html", [], [], title="nothing")
    browser.get(empty.as_uri())
    assert run("return document.body.dataset.ready") == "1" and _errors(browser) == []
    assert run("return document.querySelectorAll('#view path.seg').length") == 0
    assert browser.find_element("id", "diags").text == "none"
