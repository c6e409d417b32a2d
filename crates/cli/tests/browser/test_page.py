"""`homospline serve` in a real browser: headless Chromium driven over WebDriver (Selenium).

Opens a map, clicks S and T, gets a plan, blocks a passage, gets a re-plan, and checks what
the page shows against the command line's JSON for the same inputs; plays a mission with the
time slider; sends a malformed upload, a path outside the served folder and a 20000 x 20000
map, and checks that the page shows the command line's errors and the server keeps serving.

Needs: `HOMOSPLINE_BIN` (the release binary), Debian's `chromium` and `chromium-driver`
(`/usr/bin/chromium`, `/usr/bin/chromedriver`), `pip install selenium pytest`. Set
`HOMOSPLINE_SCREENSHOT=PATH` to keep a screenshot of the re-planned map (the README's).
"""

import json
import os
import re
import shutil
import struct
import subprocess
import tempfile
import time
import zlib
from pathlib import Path

import pytest
from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import WebDriverWait

ROOT = Path(__file__).resolve().parents[4]
BIN = os.environ.get("HOMOSPLINE_BIN", str(ROOT / "target" / "release" / "homospline"))
MAP = "maps/movingai/random-32-32-10.map"


def start_server(folder, *extra):
    """A server on a free port of 127.0.0.1; its address and the seconds it took to listen."""
    t = time.monotonic()
    proc = subprocess.Popen(
        [BIN, "serve", str(folder), "--port", "0", *extra],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    line = proc.stdout.readline()
    took = time.monotonic() - t
    m = re.search(r"http://(127\.0\.0\.1:\d+)/", line)
    assert m, f"no address in {line!r}"
    return proc, f"http://{m.group(1)}", took


@pytest.fixture(scope="module")
def browser():
    options = webdriver.ChromeOptions()
    options.binary_location = os.environ.get("CHROMIUM", "/usr/bin/chromium")
    profile = tempfile.mkdtemp()
    for flag in [
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--window-size=1500,1150",
        "--force-device-scale-factor=1",
        f"--user-data-dir={profile}",
    ]:
        options.add_argument(flag)
    service = Service(os.environ.get("CHROMEDRIVER", "/usr/bin/chromedriver"))
    driver = webdriver.Chrome(service=service, options=options)
    yield driver
    driver.quit()
    shutil.rmtree(profile, ignore_errors=True)


@pytest.fixture(scope="module")
def server():
    proc, url, took = start_server(ROOT / "fixtures")
    yield url, took
    proc.terminate()
    proc.wait(timeout=10)
    # The uploads folder goes with the server.
    assert not Path(tempfile.gettempdir(), f"homospline-serve-{proc.pid}").exists()


def wait_for(driver, predicate, what, timeout=60):
    try:
        return WebDriverWait(driver, timeout).until(lambda d: predicate(d))
    except Exception as e:  # noqa: BLE001 - say what did not happen, and what the page shows
        page_error = driver.find_element(By.ID, "error").text
        status = driver.find_element(By.ID, "status").text
        raise AssertionError(f"{what}: timed out (status {status!r}, error {page_error!r})") from e


def plans(driver):
    return int(driver.execute_script("return document.body.dataset.plans || '0'"))


def click_world(driver, x, y):
    """Clicks the drawing at world point (x, y), through the page's own transform."""
    svg = driver.find_element(By.CSS_SELECTOR, "#drawing svg")
    ox, sx, oy, sy = driver.execute_script("return state.transform")
    box = driver.execute_script(
        "const r = arguments[0].getBoundingClientRect();"
        "const v = arguments[0].viewBox.baseVal;"
        "return [r.width, r.height, v.width, v.height];",
        svg,
    )
    kx, ky = box[0] / box[2], box[1] / box[3]
    px, py = (ox + sx * x) * kx, (oy + sy * y) * ky
    # Selenium's offsets are from the element's centre.
    ActionChains(driver).move_to_element_with_offset(
        svg, round(px - box[0] / 2), round(py - box[1] / 2)
    ).click().perform()


def cli_plan(*args):
    out = tempfile.mktemp(suffix=".json")
    r = subprocess.run([BIN, "plan", *args, "--json", out], capture_output=True, text=True, cwd=ROOT / "fixtures")
    assert r.returncode in (0, 1), r.stderr
    with open(out) as f:
        return json.load(f)


def fmt(v):
    # The server writes the page's numbers with Rust's shortest round-trip form; so does repr.
    return repr(float(v))


def chosen(driver):
    el = driver.find_element(By.ID, "chosen")
    return el.get_attribute("data-letter"), float(el.get_attribute("data-length"))


def test_plan_block_and_replan_match_the_command_line(browser, server):
    url, took = server
    assert took < 1.0, f"serve took {took:.2f} s to listen"
    browser.get(f"{url}/?open={MAP}")
    wait_for(browser, lambda d: "click the start" in d.find_element(By.ID, "status").text, "the map opens")
    click_world(browser, 1.5, 27.5)
    click_world(browser, 30.5, 2.5)
    wait_for(browser, lambda d: plans(d) >= 1, "a plan")
    start, goal = browser.execute_script("return [state.start, state.goal]")
    # The clicks land in the cells clicked.
    assert int(start[0]) == 1 and int(start[1]) == 27, start
    assert int(goal[0]) == 30 and int(goal[1]) == 2, goal
    cli = cli_plan(MAP, "--start", f"{fmt(start[0])},{fmt(start[1])}", "--goal", f"{fmt(goal[0])},{fmt(goal[1])}")
    best = cli["classes"][cli["best"] - 1]
    letter, length = chosen(browser)
    assert (letter, length) == (best["letter"], best["length"])
    rows = browser.find_elements(By.CSS_SELECTOR, "#classes-table tr[data-letter]")
    assert [r.get_attribute("data-letter") for r in rows] == [c["letter"] for c in cli["classes"]]
    assert [float(r.get_attribute("data-length")) for r in rows] == [c["length"] for c in cli["classes"]]

    # Block the chosen path at its middle: the re-plan goes another way.
    path = best["path"]
    bx, by = path[len(path) // 2]
    browser.find_element(By.ID, "mode-block").click()
    radius = browser.find_element(By.ID, "block-radius")
    radius.clear()
    radius.send_keys("1.5")
    click_world(browser, bx, by)
    wait_for(browser, lambda d: plans(d) >= 2, "a re-plan")
    blocks = browser.execute_script("return state.blocks")
    assert len(blocks) == 1 and blocks[0][2] == 1.5
    b = blocks[0]
    again = cli_plan(
        MAP,
        "--start", f"{fmt(start[0])},{fmt(start[1])}",
        "--goal", f"{fmt(goal[0])},{fmt(goal[1])}",
        "--block", f"{fmt(b[0])},{fmt(b[1])},{fmt(b[2])}",
    )
    best2 = again["classes"][again["best"] - 1]
    assert chosen(browser) == (best2["letter"], best2["length"])
    assert best2["signature"] != best["signature"], "the blocked class is left"
    shot = os.environ.get("HOMOSPLINE_SCREENSHOT")
    if shot:
        browser.save_screenshot(shot)


def test_a_mission_plays_with_its_time_slider(browser, server):
    url, _ = server
    browser.get(f"{url}/?open=worlds/convex-blocked.yaml")
    wait_for(browser, lambda d: d.find_elements(By.ID, "mission-figures"), "the mission")
    total = float(browser.find_element(By.ID, "mission-figures").get_attribute("data-time"))
    t = total / 2
    browser.execute_script(
        "const s = document.getElementById('slider'); s.value = arguments[0];"
        "s.dispatchEvent(new Event('input'));",
        t,
    )
    now = browser.execute_script("return document.querySelector('#drawing svg').getCurrentTime()")
    assert abs(now - 20.0 * t / total) < 1e-6, now
    assert abs(float(browser.find_element(By.ID, "time").text) - t) <= 0.05 + 1e-9


def test_bad_requests_get_the_command_lines_errors_and_the_server_keeps_serving(browser, server):
    url, _ = server
    # A path outside the served folder.
    browser.get(f"{url}/?open=../Cargo.toml")
    wait_for(browser, lambda d: d.find_element(By.ID, "error").text, "an error")
    assert "outside the folder this server serves" in browser.find_element(By.ID, "error").text
    # A malformed upload: the command line's message, from the character it names on.
    bad = Path(tempfile.mkdtemp()) / "bad.yaml"
    bad.write_text("bounds: {min: [0, 0], max: [1]}\nstart: [0, 0]\ngoal: [1, 1]\nobstacles: []\n")
    cli = subprocess.run([BIN, "plan", str(bad)], capture_output=True, text=True)
    assert cli.returncode == 2
    message = cli.stderr.strip().split(str(bad), 1)[1]
    browser.find_element(By.ID, "upload").send_keys(str(bad))
    wait_for(browser, lambda d: "refused" in d.find_element(By.ID, "status").text, "the upload refused")
    assert browser.find_element(By.ID, "error").text.endswith(message), message
    # The server still serves.
    browser.get(f"{url}/?open={MAP}")
    wait_for(browser, lambda d: "click the start" in d.find_element(By.ID, "status").text, "the map opens again")


def white_png(path, width, height):
    """An 8-bit grey PNG of one shade, written row by row (a few hundred kB for 20000^2)."""

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    z = zlib.compressobj(9)
    row = b"\x00" + b"\xfe" * width
    body = b"".join(z.compress(row) for _ in range(height)) + z.flush()
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)))
        f.write(chunk(b"IDAT", body))
        f.write(chunk(b"IEND", b""))


def test_a_20000_square_map_gets_the_command_lines_message(browser):
    """The map reader refuses it before the memory check (past 4096^2 cells); under the
    server's memory limit, either way, the page says what the command line says."""
    folder = Path(tempfile.mkdtemp())
    white_png(folder / "huge.png", 20000, 20000)
    (folder / "huge.yaml").write_text(
        "image: huge.png\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    shutil.copy(ROOT / "fixtures" / MAP, folder / "small.map")
    limit_mb = 2000
    proc, url, _ = start_server(folder, "--memory-limit", str(limit_mb))
    try:
        browser.get(f"{url}/?open=huge.yaml")
        wait_for(browser, lambda d: d.find_element(By.ID, "error").text, "an error", timeout=120)
        shown = browser.find_element(By.ID, "error").text
        cli = subprocess.run(
            ["bash", "-c", f"ulimit -v {limit_mb * 1024}; exec \"$0\" plan huge.yaml --start 1,1 --goal 2,2", BIN],
            capture_output=True, text=True, cwd=folder,
        )
        assert cli.returncode in (2, 3), cli.stderr
        expected = cli.stderr.strip().removeprefix("error: ")
        assert shown == expected, f"page: {shown}\ncli:  {expected}"
        browser.get(f"{url}/?open=small.map")
        wait_for(browser, lambda d: "click the start" in d.find_element(By.ID, "status").text, "the server still serves")
    finally:
        proc.terminate()
        proc.wait(timeout=10)
        shutil.rmtree(folder, ignore_errors=True)
