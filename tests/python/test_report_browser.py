"""Every kind of report page, opened in a real browser (headless Chromium,
Debian's `chromium`): no image may be broken (the page's own script reports
each image's naturalWidth into #stvd-image-check, read back from the DOM
Chromium dumps once the page has loaded), and the screenshot may not be
blank. The last two tests show that both checks fail on a broken image and
on a blank page."""

import io
import json
import re
import shutil
import subprocess

import matplotlib.image
import nibabel as nib
import numpy as np
import pytest

from stvd import _report_page as report_page
from conftest import CC_BODY_L_LATERAL, CST_L, DIPY_5D, run_tool

CHECK = re.compile(r"<pre id=\"stvd-image-check\"[^>]*>(.*?)</pre>", re.S)


def chromium(tmp_path, *arguments):
    """Runs headless Chromium; returns its stdout."""
    browser = shutil.which("chromium")
    assert browser, "chromium is not installed (Debian package chromium; scripts/setup.sh installs it)"
    process = subprocess.run(
        [browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--no-first-run",
         "--disable-extensions", f"--user-data-dir={tmp_path / 'chromium-profile'}", *arguments],
        capture_output=True, text=True, timeout=600)  # a hang; Chromium starts slowly on a loaded machine
    assert process.returncode == 0, process.stderr[-2000:]
    return process.stdout


def image_check(tmp_path, page):
    """What the page's script found: {'images': n, 'broken': b, 'natural_widths': [...]}."""
    dom = chromium(tmp_path, "--virtual-time-budget=10000", "--dump-dom", page.resolve().as_uri())
    match = CHECK.search(dom)
    assert match and match.group(1), "the page's image check did not run"
    return json.loads(match.group(1))


def screenshot(tmp_path, page):
    picture = tmp_path / (page.stem + ".png")
    chromium(tmp_path, "--window-size=1280,1400", "--hide-scrollbars", f"--screenshot={picture}",
             page.resolve().as_uri())
    return matplotlib.image.imread(picture)[:, :, :3]


def require_shown(tmp_path, page):
    """The two checks of a page in the browser."""
    check = image_check(tmp_path, page)
    assert check["images"] > 0
    assert check["broken"] == 0 and all(width > 0 for width in check["natural_widths"]), check
    picture = screenshot(tmp_path, page)
    # Not blank: more than 2 % of the pixels differ from the page's
    # background, and the picture has contrast.
    background = picture[0, 0]
    different = np.abs(picture - background).max(axis=2) > 0.1
    assert different.mean() > 0.02 and picture.std() > 0.05, f"blank: different.mean() {different.mean():.3f}, " \
        f"std {picture.std():.3f}"


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    """A page of each kind, from the tool: distance, path, connectivity,
    and the cohort index of the three."""
    folder = tmp_path_factory.mktemp("pages")
    image = nib.load(DIPY_5D)
    regions = np.zeros(image.shape[:3], np.int16)
    for label, (i, j, k) in enumerate([(55, 54, 15), CST_L, (41, 51, 12), (55, 75, 9)], start=1):
        regions[i - 1:i + 2, j - 1:j + 2, k - 1:k + 2] = label
    nib.save(nib.Nifti1Image(regions, image.affine), folder / "regions.nii.gz")
    for kind in ("distance", "path", "connectivity"):
        (folder / kind).mkdir()
    run_tool("distance", DIPY_5D, "--seed-voxel", "55,54,15", "-o", folder / "distance" / "d.nii.gz", "-q",
             "--report", folder / "distance" / "report.html")
    run_tool("path", DIPY_5D, "--seed-voxel", "55,54,15", "--target-voxel", ",".join(map(str, CST_L)),
             "--target-voxel", ",".join(map(str, CC_BODY_L_LATERAL)), "-o", folder / "path" / "p.trk", "-q",
             "--report", folder / "path" / "report.html")
    run_tool("connectivity", DIPY_5D, "--labels", folder / "regions.nii.gz", "-o", folder / "connectivity" / "c.tsv",
             "-q", "--report", folder / "connectivity" / "report.html")
    run_tool("report", "--index", folder, "-o", folder / "index.html", "-q")
    return {kind: folder / kind / "report.html" for kind in ("distance", "path", "connectivity")} | {
        "index": folder / "index.html"}


@pytest.mark.parametrize("kind", ["distance", "path", "connectivity", "index"])
def test_each_kind_of_page_shows_in_a_browser(tmp_path, pages, kind):
    require_shown(tmp_path, pages[kind])


def test_a_broken_image_is_found(tmp_path, pages):
    text = pages["distance"].read_text()
    first = text.index("data:image/png;base64,") + len("data:image/png;base64,")
    broken = tmp_path / "broken.html"
    broken.write_text(text[:first] + "bm90IGEgUE5H" + text[first + 200:])  # "not a PNG"
    check = image_check(tmp_path, broken)
    assert check["images"] == 3 and check["broken"] == 1 and check["natural_widths"][0] == 0
    with pytest.raises(AssertionError):
        require_shown(tmp_path, broken)


def test_a_blank_page_is_found(tmp_path):
    # A page whose one image loads but is as white as the page.
    white = io.BytesIO()
    matplotlib.image.imsave(white, np.ones((64, 64, 3)), format="png")
    blank = tmp_path / "blank.html"
    blank.write_text(report_page.page("blank", f"<img src=\"{report_page.data_uri(white.getvalue())}\" alt=\"\">"))
    assert image_check(tmp_path, blank) == {"images": 1, "broken": 0, "natural_widths": [64]}
    with pytest.raises(AssertionError, match="different.mean"):
        require_shown(tmp_path, blank)
