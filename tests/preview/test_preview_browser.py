"""The preview page in a real browser (headless Chromium through Selenium): it shows
the image, a drag orbits the camera and the image changes, shift-drag pans, the
wheel zooms, and the options the page offers render the same view from the shell.
Skips (ctest: skipped) where Chromium, its driver or Selenium is absent."""

import os
import subprocess

import pytest

from preview_harness import CORNELL, Preview, chromium, chromium_paths, png_pixels

webdriver = pytest.importorskip("selenium.webdriver", reason="python3-selenium is not installed")
if not chromium_paths():
    pytest.skip("Chromium or chromedriver is not installed (Debian: chromium, chromium-driver)", allow_module_level=True)

from selenium.webdriver.common.action_chains import ActionChains  # noqa: E402
from selenium.webdriver.common.actions.wheel_input import ScrollOrigin  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.common.keys import Keys  # noqa: E402
from selenium.webdriver.support.ui import WebDriverWait  # noqa: E402


@pytest.fixture
def browser(tmp_path):
    driver = chromium(tmp_path / "profile")
    yield driver
    driver.quit()


def shown(driver):
    """What the page shows: body data attributes, the options field and a checksum of the image's pixels."""
    return driver.execute_script("""
        const img = document.getElementById('view');
        let sum = null;
        if (img.naturalWidth) {
            const c = document.createElement('canvas');
            c.width = img.naturalWidth; c.height = img.naturalHeight;
            const g = c.getContext('2d');
            g.drawImage(img, 0, 0);
            const d = g.getImageData(0, 0, c.width, c.height).data;
            sum = 0;
            for (let i = 0; i < d.length; i++) sum = (sum * 31 + d[i] * (i % 97 + 1)) % 1000000007;
        }
        return {phase: document.body.dataset.phase, view: Number(document.body.dataset.view),
                shownView: Number(document.body.dataset.shownView), version: Number(document.body.dataset.version),
                options: document.getElementById('options').value, pixels: sum,
                progress: document.getElementById('progress').textContent,
                error: document.getElementById('error').textContent};
    """)


def wait_page(driver, predicate, what, timeout=60):
    return WebDriverWait(driver, timeout, poll_frequency=0.05).until(
        lambda d: (lambda s: s if predicate(s) else False)(shown(d)), message=what)


def test_drag_orbits_shift_drag_pans_wheel_zooms_and_the_options_render_the_view(cli, browser, tmp_path):
    pytest.importorskip("OpenImageIO")
    options = ["--width", "160", "--height", "120", "--spp", "24", "--seed", "2"]
    with Preview(CORNELL, *options, "-o", tmp_path / "final.png") as p:
        browser.get(p.url)
        first = wait_page(browser, lambda s: s["version"] >= 1 and s["pixels"] is not None, "the first image")
        assert first["options"].startswith("--eye=") and "spp" in first["progress"]
        view = browser.find_element(By.ID, "frame")  # the image's frame takes the pointer

        # Drag: the camera orbits, the render restarts, and the image shown changes.
        ActionChains(browser).move_to_element(view).click_and_hold().move_by_offset(40, 0) \
            .move_by_offset(30, 15).release().perform()
        orbited = wait_page(browser, lambda s: s["shownView"] > first["view"] and s["options"] != first["options"],
                            "an image of the orbited view")
        assert orbited["pixels"] != first["pixels"]
        eye = lambda o: o.split()[0]  # noqa: E731
        look_at = lambda o: o.split()[1]  # noqa: E731
        assert eye(orbited["options"]) != eye(first["options"]) and look_at(orbited["options"]) == look_at(first["options"])

        # Shift-drag pans: the look-at point moves too.
        ActionChains(browser).move_to_element(view).key_down(Keys.SHIFT).click_and_hold().move_by_offset(-30, 20) \
            .release().key_up(Keys.SHIFT).perform()
        panned = wait_page(browser, lambda s: look_at(s["options"]) != look_at(orbited["options"]), "a pan")

        # The wheel zooms: the eye moves along the line of sight, the look-at point stays.
        ActionChains(browser).scroll_from_origin(ScrollOrigin.from_element(view), 0, -300).perform()
        zoomed = wait_page(browser, lambda s: eye(s["options"]) != eye(panned["options"]), "a zoom")
        assert look_at(zoomed["options"]) == look_at(panned["options"])

        # The view renders to the end; what the page shows is that view's image.
        done = wait_page(browser, lambda s: s["phase"] == "complete" and s["shownView"] == s["view"], "the final image")
        assert done["error"] == ""
        copied = done["options"]
        png, _, image_view = p.image()
        assert image_view == done["view"]
        if os.environ.get("PENUMBRA_PREVIEW_SCREENSHOT"):
            browser.save_screenshot(os.environ["PENUMBRA_PREVIEW_SCREENSHOT"])
        assert p.interrupt() == 130

    # The options the page offers, given to the command, render the image the page showed.
    subprocess.run([cli, str(CORNELL), "-q", "-o", str(tmp_path / "copied.png"), *options, *copied.split()], check=True)
    expected = png_pixels((tmp_path / "copied.png").read_bytes(), tmp_path, "a.png")
    assert (png_pixels(png, tmp_path, "b.png") == expected).all()
    assert (png_pixels((tmp_path / "final.png").read_bytes(), tmp_path, "c.png") == expected).all()


def test_the_page_says_when_the_server_is_gone(cli, browser):
    with Preview(CORNELL, "--width", "32", "--height", "32", "--spp", "100000") as p:
        browser.get(p.url)
        wait_page(browser, lambda s: s["version"] >= 1, "the first image")
        assert p.interrupt() == 130
    gone = wait_page(browser, lambda s: "does not answer" in s["error"], "the page noticing", timeout=15)
    assert gone["pixels"] is not None  # the last image stays on the page
