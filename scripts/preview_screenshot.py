#!/usr/bin/env python3
"""Takes the README's screenshot of `penumbra SCENE --preview` (docs/preview.png): the
page in headless Chromium, the camera orbited by a drag as a user would, captured
once the new view has SAMPLES samples per pixel.

usage: scripts/preview_screenshot.py OUT.png [--samples N] [-- SCENE [penumbra options...]]
Needs a build (build/bin/penumbra, or PENUMBRA_CLI) and chromium, chromium-driver and
python3-selenium (scripts/setup.sh installs them)."""

import argparse
import pathlib
import sys
import tempfile
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests" / "preview"))

from preview_harness import CORNELL, Preview, chromium, chromium_paths  # noqa: E402

DEFAULT_OPTIONS = ["--width", "512", "--height", "512", "--integrator", "path", "--spp", "4096"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     epilog=f"default after --: {CORNELL.name} {' '.join(DEFAULT_OPTIONS)}")
    parser.add_argument("out", type=pathlib.Path)
    parser.add_argument("--samples", type=int, default=16, help="samples per pixel shown (default 16)")
    argv = sys.argv[1:]
    command = argv[argv.index("--") + 1:] if "--" in argv else []
    args = parser.parse_args(argv[:argv.index("--")] if "--" in argv else argv)
    scene, options = (command[0], command[1:]) if command else (str(CORNELL), DEFAULT_OPTIONS)
    if not chromium_paths():
        sys.exit("preview_screenshot: needs chromium and chromium-driver (scripts/setup.sh installs them)")
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import WebDriverWait

    with tempfile.TemporaryDirectory() as profile, Preview(scene, *options) as p:
        driver = chromium(pathlib.Path(profile), 900, 840)
        try:
            driver.get(p.url)
            WebDriverWait(driver, 120).until(lambda d: d.execute_script("return document.body.dataset.version > 0"))
            view = driver.find_element(By.ID, "frame")
            ActionChains(driver).move_to_element(view).click_and_hold().move_by_offset(-20, 0) \
                .move_by_offset(-8, -6).release().perform()
            moved = p.wait_for(lambda s: s["view"] > 1, timeout=30)
            p.wait_for(lambda s: s["image_view"] == moved["view"] and s["image_samples"] >= args.samples,
                       timeout=600)
            time.sleep(1.5)  # the page's next poll shows that image
            driver.save_screenshot(str(args.out))
        finally:
            driver.quit()
        p.interrupt()
    print(f"preview_screenshot: wrote {args.out}")


if __name__ == "__main__":
    main()
