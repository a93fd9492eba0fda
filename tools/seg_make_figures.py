#!/usr/bin/env python3
"""Composes segmentation figures for docs/: input image | one colourised label image per model, with
titles and a palette legend of the classes that appear. Inputs come from `s3m segeval --card ... --out`
(pred/color/<stem>.png) or ground-truth label PNGs.

    /usr/bin/python3 tools/seg_make_figures.py --image rgb.png --panel "DeepLabV3+ ADE20K (mapped)" a/pred/<stem>.png \
        --panel "s3m_pspnet_small" b/pred/<stem>.png --out docs/images/seg_kitchen.png

Each --panel takes a title and a 16-bit PNG of project class ids (colourised here with the project
palette from --classes, default: the simulator/project classes.txt format "<id> <name> <r> <g> <b>").
"""
import argparse
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

DEFAULT_CLASSES = [
    (0, "unknown", 0, 0, 0), (1, "wall", 120, 120, 120), (2, "floor", 80, 50, 50), (3, "ceiling", 180, 180, 120),
    (4, "door", 8, 255, 51), (5, "window", 230, 230, 230), (6, "table", 255, 6, 82), (7, "chair", 204, 70, 3),
    (8, "sofa", 11, 102, 255), (9, "bed", 204, 5, 255), (10, "cabinet", 0, 120, 120), (11, "shelf", 140, 90, 220),
    (12, "tv_monitor", 0, 255, 194), (13, "plant", 4, 200, 3), (14, "person", 150, 5, 61), (15, "other", 255, 184, 6)]


def read_classes(path):
    if not path:
        return DEFAULT_CLASSES
    out = []
    for line in Path(path).read_text().splitlines():
        line = line.split("#")[0].split()
        if len(line) == 5:
            out.append((int(line[0]), line[1], int(line[2]), int(line[3]), int(line[4])))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--image", required=True)
    ap.add_argument("--panel", nargs=2, action="append", metavar=("TITLE", "LABELS_PNG"), required=True)
    ap.add_argument("--classes", default="")
    ap.add_argument("--width", type=int, default=320, help="panel width [px]")
    ap.add_argument("--alpha", type=float, default=0.0, help="blend labels over the image (0 = labels only)")
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    classes = read_classes(args.classes)
    lut = np.zeros((65536, 3), np.uint8)
    lut[:] = (255, 0, 255)
    for cid, _, r, g, b in classes:
        lut[cid] = (r, g, b)

    img = Image.open(args.image).convert("RGB")
    h = round(img.height * args.width / img.width)
    panels, titles, present = [img.resize((args.width, h), Image.BILINEAR)], ["input"], set()
    for title, path in args.panel:
        ids = np.asarray(Image.open(path)).astype(np.int64)
        present |= set(np.unique(ids).tolist())
        colour = Image.fromarray(lut[ids]).resize((args.width, h), Image.NEAREST)
        if args.alpha > 0:
            colour = Image.blend(panels[0], colour, args.alpha)
        panels.append(colour)
        titles.append(title)

    names = [(cid, n, (r, g, b)) for cid, n, r, g, b in classes if cid in present and cid != 0]
    legend_rows = (len(names) + 5) // 6
    top, pad = 18, 4
    canvas = Image.new("RGB", (len(panels) * (args.width + pad) - pad, top + h + 6 + legend_rows * 16), "white")
    draw = ImageDraw.Draw(canvas)
    for i, (p, t) in enumerate(zip(panels, titles)):
        x = i * (args.width + pad)
        canvas.paste(p, (x, top))
        draw.text((x + 2, 3), t, fill="black")
    for i, (_, n, rgb) in enumerate(names):
        x, y = (i % 6) * 110 + 2, top + h + 6 + (i // 6) * 16
        draw.rectangle([x, y, x + 12, y + 12], fill=rgb, outline="black")
        draw.text((x + 16, y), n, fill="black")
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    canvas.save(args.out)
    print("wrote", args.out)


if __name__ == "__main__":
    main()
