"""The report's HTML: one self-contained page per run (images as data URIs,
styles inline, nothing fetched), and the cohort index. Each run page carries
a machine-readable summary (a JSON script block) from which the cohort index
is made.

What a page may hold, whoever wrote the names and summaries it shows (a
subject folder named ``javascript:alert(1)``, a summary planted in a shared
folder): links only to relative paths inside the page's folder
(``safe_link``), images only as ``data:image/png;base64,`` URIs
(``safe_image``), JSON that no value can end or comment out of its script
block (``summary_block``), and a Content-Security-Policy that lets the page
load nothing from anywhere and run no script but its own image check."""

import base64
import hashlib
import html
import json
import os
import re
import urllib.parse

SUMMARY_ID = "stvd-report-summary"

# Every page checks its own images once loaded: the result goes into the
# element #stvd-image-check (read by the browser test through the DOM) and a
# broken image shows a red line at the top of the page for the reviewer.
IMAGE_CHECK_SCRIPT = """
window.addEventListener('load', function () {
  var images = Array.prototype.slice.call(document.images);
  var widths = images.map(function (image) { return image.complete ? image.naturalWidth : 0; });
  var broken = widths.filter(function (width) { return width === 0; }).length;
  var check = document.getElementById('stvd-image-check');
  check.textContent = JSON.stringify({images: images.length, broken: broken, natural_widths: widths});
  check.setAttribute('data-broken', String(broken));
  if (broken) {
    var line = document.getElementById('stvd-broken-images');
    line.textContent = broken + ' of ' + images.length + ' images could not be shown';
    line.hidden = false;
  }
});
"""

STYLE = """
body { font: 14px/1.45 system-ui, sans-serif; margin: 0 auto; max-width: 1500px; padding: 0 20px 40px;
       color: #1d1d1f; background: #fff; }
h1 { font-size: 22px; margin: 18px 0 4px; } h2 { font-size: 17px; margin: 26px 0 8px; border-bottom: 1px solid #ddd; }
.status { display: inline-block; padding: 1px 8px; border-radius: 4px; font-weight: 600; color: #fff; }
.status-ok { background: #2e7d32; } .status-warnings { background: #b26a00; } .status-failed { background: #c62828; }
.status-missing { background: #666; }
.warnings { background: #fff8e1; border-left: 4px solid #b26a00; padding: 6px 14px; }
.notes { background: #eef3fb; border-left: 4px solid #3465a4; padding: 6px 14px; }
.broken { background: #c62828; color: #fff; padding: 6px 14px; font-weight: 600; }
.panels { display: flex; flex-wrap: wrap; gap: 18px; align-items: flex-start; }
figure.slice { margin: 0; display: grid; grid-template-columns: 1.4em auto 1.4em;
               grid-template-rows: 1.4em auto 1.4em auto; text-align: center; font-weight: 700; }
figure.slice img { grid-column: 2; grid-row: 2; display: block; image-rendering: pixelated; }
figure.slice .top { grid-column: 2; grid-row: 1; } figure.slice .bottom { grid-column: 2; grid-row: 3; }
figure.slice .left { grid-column: 1; grid-row: 2; align-self: center; }
figure.slice .right { grid-column: 3; grid-row: 2; align-self: center; }
figure.slice figcaption { grid-column: 1 / 4; grid-row: 4; font-weight: 400; font-size: 13px; }
.colourbar { display: inline-block; width: 240px; height: 12px; vertical-align: middle; border: 1px solid #999; }
.swatch { display: inline-block; width: 14px; height: 14px; border-radius: 2px; vertical-align: middle; }
table { border-collapse: collapse; font-size: 13px; } td, th { border: 1px solid #ddd; padding: 2px 8px; text-align: left; }
th { background: #f4f4f4; } td.number { text-align: right; font-variant-numeric: tabular-nums; }
code, .mono { font-family: ui-monospace, monospace; font-size: 12.5px; overflow-wrap: anywhere; }
.cohort td { vertical-align: middle; } .cohort img { display: block; max-width: 180px; }
"""


def data_uri(png):
    """An image embedded in the page."""
    return "data:image/png;base64," + base64.b64encode(png).decode("ascii")


_PNG_DATA_URI = re.compile(r"data:image/png;base64,[A-Za-z0-9+/]*={0,2}")


def safe_image(uri):
    """``uri`` when it is a ``data:image/png;base64,`` URI (the only images a
    page embeds), else None: an ``http://`` thumbnail in a summary would make
    the page fetch from the network."""
    return uri if isinstance(uri, str) and _PNG_DATA_URI.fullmatch(uri) else None


def safe_link(relative_path):
    """The href of a file at ``relative_path`` (relative to the page's
    folder, as ``os.path.relpath`` gives it), or None when the file is not
    inside the page's folder (an absolute path, a '..' part). Every part is
    percent-encoded and the link starts with './': a folder named
    ``javascript:alert(1)`` becomes ``./javascript%3Aalert%281%29/...``, a
    relative path, never a URL scheme."""
    if not isinstance(relative_path, str) or not relative_path or os.path.isabs(relative_path):
        return None
    parts = relative_path.replace(os.sep, "/").split("/")
    if any(part in ("", ".", "..") for part in parts):
        return None
    return "./" + "/".join(urllib.parse.quote(part, safe="") for part in parts)


def escape(value):
    return html.escape(str(value), quote=True)


def number_text(value, decimals=1):
    if value is None:
        return "n/a"
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, int):
        return f"{value:,}"
    if isinstance(value, float):
        if value != value:
            return "n/a"
        return f"{value:,.{decimals}f}"
    return str(value)


# Nothing is loaded from anywhere (default-src 'none'): images only from
# data: URIs, styles only inline, and no script but the image check, named
# by its hash. A page opened from a shared folder can neither fetch nor
# send anything, whatever names and summaries it shows.
CONTENT_SECURITY_POLICY = (
    "default-src 'none'; img-src data:; style-src 'unsafe-inline'; script-src 'sha256-"
    + base64.b64encode(hashlib.sha256(IMAGE_CHECK_SCRIPT.encode("utf-8")).digest()).decode("ascii")
    + "'; base-uri 'none'; form-action 'none'")


def page(title, body):
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<meta http-equiv=\"Content-Security-Policy\" content=\"{CONTENT_SECURITY_POLICY}\">\n"
            f"<title>{escape(title)}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n"
            "<div id=\"stvd-broken-images\" class=\"broken\" hidden></div>\n"
            f"{body}\n"
            "<pre id=\"stvd-image-check\" hidden></pre>\n"
            f"<script>{IMAGE_CHECK_SCRIPT}</script>\n</body>\n</html>\n")


def script_json(value):
    """JSON for a script block that no value can end or comment out: '<',
    '>' and '&' are written as \\u escapes (the same JSON), so that neither
    ``</script>`` nor ``<!--<script>``, which would make the parser swallow
    the page's own script, can appear in it."""
    text = json.dumps(value, sort_keys=True)
    return text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def summary_block(summary):
    """The run's summary as a JSON script block (``script_json``)."""
    return f"<script type=\"application/json\" id=\"{SUMMARY_ID}\">{script_json(summary)}</script>"


_SUMMARY_PATTERN = re.compile(r"<script type=\"application/json\" id=\"" + SUMMARY_ID + r"\">(.*?)</script>", re.S)


def read_summary(page_text):
    """The summary block of a run page, or None when the page has none (or
    a block that is not a JSON object)."""
    match = _SUMMARY_PATTERN.search(page_text)
    if not match:
        return None
    summary = json.loads(match.group(1))
    return summary if isinstance(summary, dict) else None


def slice_figure(panel, png, caption):
    letters = panel.letters
    return (f"<figure class=\"slice\" data-plane=\"{panel.plane}\" data-left=\"{letters['left']}\" "
            f"data-right=\"{letters['right']}\" data-top=\"{letters['top']}\" data-bottom=\"{letters['bottom']}\">"
            f"<span class=\"top\">{letters['top']}</span><span class=\"left\">{letters['left']}</span>"
            f"<img src=\"{data_uri(png)}\" alt=\"{escape(caption)}\">"
            f"<span class=\"right\">{letters['right']}</span><span class=\"bottom\">{letters['bottom']}</span>"
            f"<figcaption>{escape(caption)}</figcaption></figure>")


def colour_bar(colours, low, high, unit):
    stops = ", ".join(colours)
    return (f"{escape(low)} <span class=\"colourbar\" style=\"background: linear-gradient(to right, {stops})\">"
            f"</span> {escape(high)} {escape(unit)}")


def key_value_table(rows, table_id=None):
    identifier = f" id=\"{table_id}\"" if table_id else ""
    cells = "".join(f"<tr><th>{escape(key)}</th><td class=\"mono\">{escape(value)}</td></tr>" for key, value in rows)
    return f"<table{identifier}>{cells}</table>"


def table(header, rows, table_id=None, raw_columns=()):
    """A table; values in ``raw_columns`` are HTML already, numbers are
    right-aligned."""
    identifier = f" id=\"{table_id}\"" if table_id else ""
    head = "".join(f"<th>{escape(h)}</th>" for h in header)
    body = []
    for row in rows:
        cells = []
        for column, value in enumerate(row):
            if column in raw_columns:
                cells.append(f"<td>{value}</td>")
            elif isinstance(value, (int, float)) and not isinstance(value, bool):
                cells.append(f"<td class=\"number\">{escape(number_text(value, 2))}</td>")
            else:
                cells.append(f"<td>{escape(value)}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    return f"<table{identifier}><tr>{head}</tr>{''.join(body)}</table>"


STATUSES = ("ok", "warnings", "failed", "missing")


def status_badge(status):
    status = status if status in STATUSES else "missing"
    return f"<span class=\"status status-{status}\">{status}</span>"


def item_list(items, css_class, list_id):
    if not items:
        return ""
    return (f"<div class=\"{css_class}\" id=\"{list_id}\"><ul>" +
            "".join(f"<li>{escape(item)}</li>" for item in items) + "</ul></div>")
