"""The figure of docs/fod.md, "Paths through the crossing": the coronal
panels (slice j = 54) of the four pages scripts/fod_crossing_qc.sh writes,
cut to the box around the crossings and the slab's slices, one above the
other (tensor, FOD; corticospinal, callosal).

Usage: /usr/bin/python3 scripts/fod_crossing_figure.py OUTDIR FIGURE.png
(OUTDIR: the folder of scripts/fod_crossing_qc.sh, default out/fod_crossing).
The panels are the pages' own PNGs (data URIs), drawn at 3.5 pixels per
voxel on the 112 x 112 grid; the tensors' panel spans their 32 slices,
the FOD's the slab's 12 (the tensors' 10 to 21)."""

import base64
import io
import re
import sys

from PIL import Image, ImageDraw

PANEL = re.compile(r'<img src="data:image/png;base64,([A-Za-z0-9+/=]*)" alt="coronal slice j = 54"')
PIXELS_PER_VOXEL = 3.5
FIRST_SLICE, SLICES, TENSOR_SLICES = 10, 12, 32
BOX_I = (30, 82)  # the box's voxels along i, as the script's mask
WIDTH = 112
SCALE = 3


def panel(page):
    found = PANEL.search(open(page, encoding="utf-8").read())
    if found is None:
        raise SystemExit(f"{page}: no coronal panel of slice j = 54")
    image = Image.open(io.BytesIO(base64.b64decode(found.group(1)))).convert("RGB")
    if round(image.size[1] / PIXELS_PER_VOXEL) == TENSOR_SLICES:  # superior at the top
        top = (TENSOR_SLICES - FIRST_SLICE - SLICES) * PIXELS_PER_VOXEL
        image = image.crop((0, round(top), image.size[0], round(top + SLICES * PIXELS_PER_VOXEL)))
    # Neurological display: the patient's left (large i) on the left.
    left = (WIDTH - BOX_I[1]) * PIXELS_PER_VOXEL - 6
    right = (WIDTH - BOX_I[0]) * PIXELS_PER_VOXEL + 6
    image = image.crop((round(left), 0, round(right), image.size[1]))
    return image.resize((image.size[0] * SCALE, image.size[1] * SCALE), Image.NEAREST)


def main(folder, figure):
    rows = [(label, panel(f"{folder}/{name}.html")) for name, label in
            (("cst_tensor", "CST, tensor"), ("cst_fod", "CST, FOD"), ("cc_tensor", "CC, tensor"), ("cc_fod", "CC, FOD"))]
    margin, text_width = 8, 110
    width = text_width + max(image.size[0] for _, image in rows) + margin
    height = margin + sum(image.size[1] + margin for _, image in rows)
    out = Image.new("RGB", (width, height), "white")
    draw = ImageDraw.Draw(out)
    y = margin
    for label, image in rows:
        draw.text((margin, y + image.size[1] // 2 - 6), label, fill="black")
        out.paste(image, (text_width, y))
        y += image.size[1] + margin
    out.save(figure)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "out/fod_crossing", sys.argv[2] if len(sys.argv) > 2 else
         "out/fod_crossing/coronal.png")
