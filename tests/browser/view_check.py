"""The 3D view in a real browser: `c5 simulate`'s page opened in headless Chromium with the
network blocked. No console error, no request leaves the file; the first and the last frame,
reached through the page's own time slider, show the robot (pixels in the legs' colours) and
differ where the platform moved. The screenshots are kept beside the page.

    python tests/browser/view_check.py out/view.html [--chromium /usr/bin/chromium]

Needs `playwright` (the Python package; its browser download is not used) and `pillow`.
"""

import argparse
import pathlib
import sys

import numpy as np
from PIL import Image
from playwright.sync_api import sync_playwright

FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-quic",
    # Belt and braces beside the request router below: no name resolves.
    "--host-resolver-rules=MAP * ~NOTFOUND",
]


def colour(hex_colour):
    return tuple(int(hex_colour[1 + 2 * k : 3 + 2 * k], 16) for k in range(3))


def pixels(image, box):
    """The pixels of `image` inside `box`, as signed integers (height, width, RGB)."""
    return np.asarray(image.crop(box).convert("RGB"), dtype=np.int32)


def near(image, rgb, box, tolerance=10):
    """How many pixels of `image` inside `box` are within `tolerance` of `rgb` per channel."""
    return int((np.abs(pixels(image, box) - np.array(rgb)) <= tolerance).all(axis=2).sum())


def platform_pixels(image, box):
    """Where the platform's bluish grey (#7f9bbf under the mesh's lighting) is."""
    r, g, b = np.moveaxis(pixels(image, box), 2, 0)
    return (b - r >= 20) & (b - r <= 90) & (r < g) & (g < b) & (r > 50)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("page", type=pathlib.Path)
    parser.add_argument("--chromium", default="/usr/bin/chromium")
    args = parser.parse_args()
    page_path = args.page.resolve()
    shots = page_path.parent
    problems, left = [], []
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=args.chromium, args=FLAGS)
        page = browser.new_page(viewport={"width": 1280, "height": 860})
        page.on(
            "console",
            lambda m: problems.append(f"console {m.type}: {m.text}")
            if m.type == "error"
            else None,
        )
        page.on("pageerror", lambda e: problems.append(f"page error: {e}"))

        def route(r):
            if r.request.url.startswith("file://") and r.request.url.split("#")[0] == page_path.as_uri():
                r.continue_()
            else:
                left.append(r.request.url)
                r.abort()

        page.route("**/*", route)
        page.goto(page_path.as_uri())
        page.wait_for_function("window.c5view && window.c5view.ready === true", timeout=60_000)
        frames = page.evaluate("window.c5view.frames")
        box = page.evaluate(
            "(() => { const r = document.getElementById('figure').getBoundingClientRect();"
            " return [r.left, r.top, r.right, r.bottom].map(Math.round); })()"
        )
        images, readouts = [], []
        for k in (0, frames - 1):
            # Through the slider, as a person would drag it.
            page.evaluate(
                "k => { const s = document.getElementById('slider'); s.value = String(k);"
                " s.dispatchEvent(new Event('input')); }",
                k,
            )
            page.wait_for_function(f"window.c5view.shown === {k}", timeout=20_000)
            path = shots / f"view-frame-{k}.png"
            page.screenshot(path=str(path))
            images.append(Image.open(path).convert("RGB"))
            readouts.append(page.evaluate(f"window.c5view.readout[{k}]"))
        browser.close()

    failures = list(problems)
    if left:
        failures.append(f"requests left the file: {left}")
    for k, (image, readout) in enumerate(zip(images, readouts)):
        for i, c in enumerate(readout["colours"]):
            count = near(image, colour(c), box)
            print(f"frame {k}: leg {i + 1} colour {c}: {count} pixels")
            if count < 30:
                failures.append(f"frame {k}: leg {i + 1} ({c}) not drawn: {count} pixels")
    changed = np.abs(pixels(images[0], box) - pixels(images[1], box)).max(axis=2) > 40
    platform = platform_pixels(images[0], box) | platform_pixels(images[1], box)
    moved = int((changed & platform).sum())
    print(
        f"{int(changed.sum())} pixels differ between the first and the last frame, "
        f"{moved} of them on the platform ({int(platform.sum())} platform pixels)"
    )
    if platform.sum() < 500:
        failures.append(f"the platform is not drawn: {int(platform.sum())} pixels")
    if moved < 200:
        failures.append(f"the platform did not move between the frames: {moved} pixels")
    print(f"screenshots: {shots / 'view-frame-0.png'}, {shots / f'view-frame-{frames - 1}.png'}")
    if failures:
        print("FAILED:\n  " + "\n  ".join(failures))
        sys.exit(1)
    print("the view opens offline, shows the robot and moves it")


if __name__ == "__main__":
    main()
