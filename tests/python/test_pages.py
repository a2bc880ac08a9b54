"""What a QC page and a cohort index may hold, whoever named the folders and
wrote the summaries they show (a shared study folder): links only to
relative paths inside the page's folder, images only as data: PNGs, JSON
that cannot end or comment out its script block, a Content-Security-Policy
that loads nothing; what an index reads (regular files only, of bounded
size) and never writes over (docs/reliability.md, "Security")."""

import html
import html.parser
import http.server
import json
import os
import re
import shutil
import subprocess
import threading
import urllib.parse

import pytest

from stvd import _report_page as report_page
from conftest import DIPY_5D, TOOL, run_tool
from test_report_browser import CHECK, chromium, image_check

HOSTILE_FOLDER = "javascript:alert(document.domain)"
DATA_PNG = re.compile(r"data:image/png;base64,[A-Za-z0-9+/]*={0,2}")
TOO_LARGE = 300 << 20  # more than a page may have (stvd._files.PAGE_BYTES, 256 MiB)
HOSTILE_SUBJECT = "</script><!--<script>s01"


class Elements(html.parser.HTMLParser):
    """Every element's tag and attributes, and the text of each script
    element, as an HTML parser sees them."""

    def __init__(self, text):
        super().__init__()
        self.elements, self.scripts, self._script = [], [], None
        self.feed(text)

    def handle_starttag(self, tag, attributes):
        self.elements.append((tag, dict(attributes)))
        if tag == "script":
            self._script = (dict(attributes), [])

    def handle_data(self, data):
        if self._script is not None:
            self._script[1].append(data)

    def handle_endtag(self, tag):
        if tag == "script" and self._script is not None:
            self.scripts.append((self._script[0], "".join(self._script[1])))
            self._script = None


def require_safe_page(text):
    """Every href a relative path inside the page's folder, every src a
    data: PNG, the one executable script the image check, the summary
    (when there is one) free of '<', and the security policy in place."""
    parsed = Elements(text)
    links = [attributes["href"] for tag, attributes in parsed.elements if "href" in attributes]
    sources = [attributes["src"] for tag, attributes in parsed.elements if "src" in attributes]
    for href in links:
        parts = urllib.parse.urlsplit(href)
        assert parts.scheme == "" and parts.netloc == "", href
        assert href.startswith("./") and ".." not in urllib.parse.unquote(parts.path).split("/"), href
    for source in sources:
        assert DATA_PNG.fullmatch(source), source[:80]
    for tag, attributes in parsed.elements:  # no handler an attribute value could have opened
        assert not any(name.startswith("on") for name in attributes), (tag, attributes)
    executable = [body for attributes, body in parsed.scripts if attributes.get("type") != "application/json"]
    assert executable == [report_page.IMAGE_CHECK_SCRIPT]
    for attributes, body in parsed.scripts:
        if attributes.get("type") == "application/json":
            assert "<" not in body and json.loads(body)
    policies = [a for tag, a in parsed.elements if tag == "meta" and a.get("http-equiv") == "Content-Security-Policy"]
    assert len(policies) == 1 and "default-src 'none'" in policies[0]["content"]
    assert "img-src data:" in policies[0]["content"]
    return links, sources


@pytest.fixture(scope="module")
def page_folder(tmp_path_factory):
    """A folder of reports as a shared study folder may hold it: a real run
    page; a copy in a folder named like a script URL; a page whose summary
    was written by someone else (a subject name that tries to end the script
    block, an http:// thumbnail, a status that tries to leave its attribute)."""
    folder = tmp_path_factory.mktemp("pages")
    (folder / "run").mkdir()
    run_tool("distance", DIPY_5D, "--seed-voxel", "55,54,15", "-o", folder / "run" / "d.nii.gz", "-q", "--stats",
             folder / "run" / "d.json", "--report", folder / "run" / "report.html")
    (folder / HOSTILE_FOLDER).mkdir()
    shutil.copy(folder / "run" / "report.html", folder / HOSTILE_FOLDER / "report.html")
    (folder / "planted").mkdir()
    (folder / "planted" / "report.html").write_text("<html><body>" + report_page.summary_block({
        "subject": HOSTILE_SUBJECT, "status": "ok\" onmouseover=\"alert(1)", "warnings": "many",
        "thumbnail": "http://127.0.0.1:9/pixel.png", "figures": {"seconds": 1.5, "<b>x</b>": [1, 2]},
        "error": "<img src=x onerror=alert(1)>"}) + "</body></html>")
    return folder


def test_an_index_links_only_inside_its_folder_and_embeds_only_data_pngs(page_folder):
    # The index in the folder itself, as a cohort's.
    output = page_folder / "index.html"
    process = subprocess.run([str(TOOL), "report", "--index", str(page_folder), "-o", str(output), "-q"],
                             capture_output=True, text=True, timeout=120)
    assert process.returncode == 0, process.stderr
    text = output.read_text()
    links, sources = require_safe_page(text)
    assert "./javascript%3Aalert%28document.domain%29/report.html" in links
    assert "./run/report.html" in links
    assert not any("javascript:" in link or "http" in link for link in links)
    assert len(sources) == 2  # the two real thumbnails; the planted http:// one is left out
    assert "<img src=x" not in text and "<b>x</b>" not in text
    assert html.escape(HOSTILE_SUBJECT, quote=True) in text
    output.unlink()


def test_an_index_reads_only_regular_files_of_bounded_size(page_folder, tmp_path):
    # A FIFO and a link to /dev/zero named report.html, and a page too large
    # to read (sparse: no disk taken), next to a real one: the index is made
    # at once, and lists them without a page.
    folder = tmp_path / "study"
    (folder / "run").mkdir(parents=True)
    shutil.copy(page_folder / "run" / "report.html", folder / "run" / "report.html")
    (folder / "fifo").mkdir()
    os.mkfifo(folder / "fifo" / "report.html")
    (folder / "zero").mkdir()
    os.symlink("/dev/zero", folder / "zero" / "report.html")
    (folder / "huge").mkdir()
    with open(folder / "huge" / "report.html", "wb") as huge:
        huge.truncate(TOO_LARGE)
    output = folder / "index.html"
    process = subprocess.run([str(TOOL), "report", "--index", str(folder), "-o", str(output), "-q"],
                             capture_output=True, text=True, timeout=120)
    assert process.returncode == 0, process.stderr
    text = output.read_text()
    assert "./run/report.html" in text
    for name in ("fifo", "zero", "huge"):
        assert re.search(r"<td>" + name + r"</td><td><span class=\"status status-missing\">", text), name


def test_a_run_page_keeps_its_json_in_its_script_block(page_folder, tmp_path):
    output = tmp_path / "hostile.html"
    run_tool("report", "--stats", page_folder / "run" / "d.json", "--subject", HOSTILE_SUBJECT, "-o", output, "-q")
    text = output.read_text()
    require_safe_page(text)
    summary = report_page.read_summary(text)
    assert summary["subject"] == HOSTILE_SUBJECT


class CountingServer:
    """An HTTP server on the loopback interface that counts the requests it
    gets: a page that fetches anything from the network shows here."""

    def __init__(self):
        self.requests = []
        owner = self

        class Handler(http.server.BaseHTTPRequestHandler):
            def do_GET(self):
                owner.requests.append(self.path)
                self.send_response(404)
                self.end_headers()

            def log_message(self, *args):
                pass

        self.server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.port = self.server.server_address[1]
        self.thread = threading.Thread(target=self.server.serve_forever, daemon=True)
        self.thread.start()

    def close(self):
        self.server.shutdown()
        self.server.server_close()


def test_in_a_browser_nothing_is_fetched_and_the_image_check_still_runs(page_folder, tmp_path):
    server = CountingServer()
    try:
        folder = tmp_path / "study"
        folder.mkdir()
        (folder / "planted").mkdir()
        (folder / "planted" / "report.html").write_text("<html><body>" + report_page.summary_block({
            "subject": "planted", "status": "ok", "thumbnail": f"http://127.0.0.1:{server.port}/thumbnail.png"})
            + "</body></html>")
        (folder / "run").mkdir()
        run_tool("report", "--stats", page_folder / "run" / "d.json", "--subject", HOSTILE_SUBJECT, "-o",
                 folder / "run" / "report.html", "-q")
        run_tool("report", "--index", folder, "-o", folder / "index.html", "-q")
        for page in (folder / "index.html", folder / "run" / "report.html"):
            dom = chromium(tmp_path, "--virtual-time-budget=10000", "--dump-dom", page.resolve().as_uri())
            match = CHECK.search(dom)
            assert match and match.group(1), f"{page.name}: the page's image check did not run"
            check = json.loads(match.group(1))
            assert check["broken"] == 0, check
        assert image_check(tmp_path, folder / "run" / "report.html")["images"] == 3
        assert server.requests == []
    finally:
        server.close()


def test_the_index_never_writes_over_a_page_it_reads(page_folder, tmp_path):
    page = page_folder / "run" / "report.html"
    before = page.read_bytes()
    process = subprocess.run([str(TOOL), "report", "--index", str(page_folder), "-o", str(page), "-q"],
                             capture_output=True, text=True, timeout=120)
    assert process.returncode == 2, process.stderr
    assert process.stderr.count("\n") == 1 and "the QC report is the report of" in process.stderr, process.stderr
    assert page.read_bytes() == before


def test_a_run_report_reads_no_fifo_and_no_device(page_folder, tmp_path):
    os.mkfifo(tmp_path / "d.json")
    os.symlink("/dev/zero", tmp_path / "zero.json")
    for statistics in (tmp_path / "d.json", tmp_path / "zero.json"):
        process = subprocess.run([str(TOOL), "report", "--stats", str(statistics), "-o", str(tmp_path / "r.html")],
                                 capture_output=True, text=True, timeout=120)
        assert process.returncode == 3, process.stderr
        assert "not a regular file" in process.stderr and process.stderr.count("\n") == 1, process.stderr
    assert not (tmp_path / "r.html").exists()


def test_links_and_images_of_the_page_module():
    assert report_page.safe_link("javascript:alert(1)/report.html") == "./javascript%3Aalert%281%29/report.html"
    assert report_page.safe_link("s 01/report.html") == "./s%2001/report.html"
    for outside in ("../other/report.html", "/etc/report.html", "a/../../report.html", ""):
        assert report_page.safe_link(outside) is None, outside
    assert report_page.safe_image("data:image/png;base64,iVBORw0KGgo=") == "data:image/png;base64,iVBORw0KGgo="
    for other in ("http://example.org/x.png", "data:image/svg+xml;base64,PHN2Zz4=", "data:image/png;base64,\"x",
                  "javascript:alert(1)", None, 3):
        assert report_page.safe_image(other) is None, other
    block = report_page.summary_block({"subject": "</script><!--<script>&"})
    assert block.count("<") == 2 and report_page.read_summary(block)["subject"] == "</script><!--<script>&"
