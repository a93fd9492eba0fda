#!/usr/bin/env python3
"""Trains s3m's small PSPNet-style segmentation network on simulator output and exports it to ONNX.

Network ("s3m_pspnet_small"): a light MobileNet-like backbone (stride 8, depthwise-separable blocks)
and a PSPNet pyramid pooling head (bins 1, 2, 4 over the stride-8 features, 1x1 reductions,
bilinear upsampling, concatenation, 3x3 fusion conv, 1x1 classifier). It outputs raw logits over the
project's 16 indoor classes at stride 8 of the input (half-pixel grid); OnnxSegmenter upsamples the
class probabilities to the camera image. Channel 0 ("unknown") is never trained (ignore index) and
the model card lists it in ignore_classes.

Data: sequences written by `s3m sim ... --out DIR` (TUM layout): DIR/rgb/<name>.png and
DIR/labels/<stem>.png (16-bit project class ids, 0 = unknown). Pass training and validation folders:

  /usr/bin/python3 tools/train_segmenter.py --train sim/office_s1 sim/office_s2 --val sim/office_s9 \
      --out models/s3m_pspnet_small.onnx --minutes 15 --threads 2

Runs on CPU with Debian's python3-torch; training stops after --minutes (wall clock) or --epochs.
Writes the ONNX file, prints validation mIoU (PyTorch side; the C++ number comes from `s3m segeval`).
Built from the PSPNet idea (Zhao et al., CVPR 2017); no third-party code copied.
"""
import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

try:
    import torch
except ImportError:
    sys.exit("train_segmenter: PyTorch is missing: scripts/setup.sh --with-training installs it (python3-torch)")
import torch.nn as nn
import torch.nn.functional as F

NUM_CLASSES = 16  # s3m/core/classes.hpp: unknown .. other
CLASS_NAMES = ["unknown", "wall", "floor", "ceiling", "door", "window", "table", "chair", "sofa", "bed",
               "cabinet", "shelf", "tv_monitor", "plant", "person", "other"]
MEAN = (0.485, 0.456, 0.406)  # ImageNet statistics, RGB; also written into the model card
STD = (0.229, 0.224, 0.225)


def conv_bn(cin, cout, k=3, stride=1, groups=1, dilation=1):
    pad = dilation * (k - 1) // 2
    return nn.Sequential(nn.Conv2d(cin, cout, k, stride, pad, dilation=dilation, groups=groups, bias=False),
                         nn.BatchNorm2d(cout), nn.ReLU(inplace=True))


class SepBlock(nn.Module):
    """Depthwise 3x3 + pointwise 1x1 (MobileNet), with a residual when shapes allow."""

    def __init__(self, cin, cout, stride=1, dilation=1):
        super().__init__()
        self.dw = conv_bn(cin, cin, 3, stride, groups=cin, dilation=dilation)
        self.pw = conv_bn(cin, cout, 1)
        self.residual = stride == 1 and cin == cout

    def forward(self, x):
        y = self.pw(self.dw(x))
        return x + y if self.residual else y


class PyramidPooling(nn.Module):
    """PSPNet head. Pools with fixed kernels (feature size / bin) so the ONNX graph has plain
    AveragePool ops that OpenCV DNN reads; the input size is fixed at export anyway."""

    def __init__(self, cin, feat_hw, bins=(1, 2, 4, 8), reduce=24):
        super().__init__()
        h, w = feat_hw
        for b in bins:
            assert h % b == 0 and w % b == 0, f"feature size {h}x{w} not divisible by bin {b}"
        self.kernels = [(h // b, w // b) for b in bins]
        self.reduce = nn.ModuleList([conv_bn(cin, reduce, 1) for _ in bins])
        self.out_channels = cin + reduce * len(bins)

    def forward(self, x):
        outs = [x]
        for k, red in zip(self.kernels, self.reduce):
            y = red(F.avg_pool2d(x, k, k))
            # constant scale factors (not a target size) keep Shape/Slice ops out of the ONNX graph
            outs.append(F.interpolate(y, scale_factor=(float(k[0]), float(k[1])), mode="bilinear", align_corners=False))
        return torch.cat(outs, 1)


class PSPNetSmall(nn.Module):
    def __init__(self, input_hw, num_classes=NUM_CLASSES, width=1.0, bins=(1, 2, 4)):
        super().__init__()
        c = [int(v * width) for v in (16, 32, 64, 96)]
        self.backbone = nn.Sequential(
            conv_bn(3, c[0], 3, 2),           # /2
            SepBlock(c[0], c[1], 2),          # /4
            SepBlock(c[1], c[1]),
            SepBlock(c[1], c[2], 2),          # /8
            SepBlock(c[2], c[2]),
            SepBlock(c[2], c[3], 1, dilation=2),
            SepBlock(c[3], c[3], 1, dilation=4),
        )
        feat_hw = (input_hw[0] // 8, input_hw[1] // 8)
        self.ppm = PyramidPooling(c[3], feat_hw, bins)
        self.fuse = conv_bn(self.ppm.out_channels, 64, 3)
        self.classifier = nn.Conv2d(64, num_classes, 1)

    def forward(self, x):
        return self.classifier(self.fuse(self.ppm(self.backbone(x))))


# ---------------------------------------------------------------- data
def read_sequence(folder: Path, input_hw, label_scale):
    """Loads one sequence: images (N,3,h,w) float RGB in [0,1] resized like OnnxSegmenter does
    (bilinear, half-pixel, no anti-aliasing = cv::resize INTER_LINEAR), labels (N,2h,2w) int64
    (N, s*h, s*w) int64 resized nearest (the loss compares logits upsampled to s x the input size)."""
    from PIL import Image  # python3-pil comes with python3-matplotlib; no OpenCV for Python needed
    rgb_dir, lab_dir = folder / "rgb", folder / "labels"
    if not rgb_dir.is_dir() or not lab_dir.is_dir():
        sys.exit(f"train_segmenter: {folder} has no rgb/ and labels/ folders (expected `s3m sim --out` output)")
    h, w = input_hw
    images, labels = [], []
    for rgb_path in sorted(p for p in rgb_dir.iterdir() if p.suffix in (".png", ".jpg")):
        lab_path = lab_dir / (rgb_path.stem + ".png")
        if not lab_path.exists():
            sys.exit(f"train_segmenter: no label image {lab_path} for {rgb_path}")
        rgb = np.asarray(Image.open(rgb_path).convert("RGB"))
        lab = np.asarray(Image.open(lab_path))
        if lab.ndim != 2 or lab.shape != rgb.shape[:2]:
            sys.exit(f"train_segmenter: {lab_path} must be one channel of the image's size")
        x = torch.from_numpy(rgb.copy()).permute(2, 0, 1)[None].float() / 255.0
        images.append(F.interpolate(x, size=(h, w), mode="bilinear", align_corners=False)[0])
        y = torch.from_numpy(lab.astype(np.int64))[None, None].float()
        labels.append(F.interpolate(y, size=(label_scale * h, label_scale * w), mode="nearest")[0, 0].long())
    if not images:
        sys.exit(f"train_segmenter: {rgb_dir} holds no images")
    return torch.stack(images), torch.stack(labels)


def load(folders, input_hw, label_scale):
    xs, ys = zip(*(read_sequence(Path(f), input_hw, label_scale) for f in folders))
    return torch.cat(xs), torch.cat(ys)


def normalise(x):
    mean = torch.tensor(MEAN).view(1, 3, 1, 1)
    std = torch.tensor(STD).view(1, 3, 1, 1)
    return (x - mean) / std


def augment(x, y, gen):
    """Horizontal flips and brightness/contrast/colour jitter (the simulator's lighting is clean)."""
    flip = torch.rand(x.shape[0], generator=gen) < 0.5
    x[flip] = x[flip].flip(-1)
    y[flip] = y[flip].flip(-1)
    gain = 1.0 + 0.25 * (torch.rand(x.shape[0], 3, 1, 1, generator=gen) - 0.5)
    bias = 0.4 * (torch.rand(x.shape[0], 1, 1, 1, generator=gen) - 0.5)
    return x * gain + bias + 0.05 * torch.randn(x.shape, generator=gen), y


def confusion(pred, gt, n=NUM_CLASSES):
    keep = gt > 0
    return torch.bincount(gt[keep] * n + pred[keep], minlength=n * n).view(n, n)


def miou(cm):
    tp = cm.diag().double()
    union = cm.sum(0).double() + cm.sum(1).double() - tp
    present = cm.sum(1) > 0
    present[0] = False
    iou = tp / union.clamp(min=1)
    return iou[present].mean().item(), {CLASS_NAMES[i]: round(iou[i].item(), 3) for i in range(1, NUM_CLASSES) if present[i]}


def evaluate(model, x, y, batch=32):
    model.eval()
    cm = torch.zeros(NUM_CLASSES, NUM_CLASSES, dtype=torch.long)
    with torch.no_grad():
        for i in range(0, len(x), batch):
            logits = model(x[i:i + batch])
            up = F.interpolate(logits, size=y.shape[-2:], mode="bilinear", align_corners=False)
            cm += confusion(up.argmax(1).flatten(), y[i:i + batch].flatten())
    model.train()
    return miou(cm)


def class_weights(y):
    """Square-root inverse-frequency weights so small objects (chairs, monitors) get learned."""
    counts = torch.bincount(y.flatten(), minlength=NUM_CLASSES).double()
    freq = counts / counts[1:].sum()
    w = torch.where(counts > 0, 1.0 / freq.clamp(min=1e-6).sqrt(), torch.zeros_like(freq))
    w[0] = 0.0
    return (w / w[1:][counts[1:] > 0].mean()).clamp(max=10.0).float()


def export(model, input_hw, path: Path):
    model.eval()
    dummy = torch.zeros(1, 3, *input_hw)
    torch.onnx.export(model, dummy, str(path), input_names=["input"], output_names=["logits"], opset_version=11,
                      do_constant_folding=True)
    import onnx
    from onnx import numpy_helper
    m = onnx.load(str(path))
    # torch shares identical weight tensors through Identity nodes, which OpenCV 4.6 cannot read:
    # give each consumer its own copy of the initializer instead.
    inits = {i.name: i for i in m.graph.initializer}
    for node in [n for n in m.graph.node if n.op_type == "Identity" and n.input[0] in inits]:
        arr = numpy_helper.to_array(inits[node.input[0]])
        m.graph.initializer.append(numpy_helper.from_array(arr, node.output[0]))
        m.graph.node.remove(node)
    onnx.checker.check_model(m)
    onnx.save(m, str(path))
    ops = sorted({n.op_type for n in m.graph.node})
    print(f"exported {path}: ops {ops}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--train", nargs="+", help="training sequence folders (s3m sim output)")
    ap.add_argument("--val", nargs="*", default=[], help="held-out sequence folders")
    ap.add_argument("--out", required=True, help="output .onnx path")
    ap.add_argument("--height", type=int, default=128)
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--label-scale", type=int, default=1, help="loss resolution as a multiple of the input size")
    ap.add_argument("--bins", type=int, nargs="+", default=[1, 2, 4],
                    help="pyramid pooling bins; must divide the stride-8 feature size")
    ap.add_argument("--minutes", type=float, default=15.0, help="wall-clock training budget")
    ap.add_argument("--epochs", type=int, default=1000)
    ap.add_argument("--batch", type=int, default=8)
    ap.add_argument("--lr", type=float, default=3e-3)
    ap.add_argument("--threads", type=int, default=1, help="torch threads (1 is fastest on a busy machine)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--export-only", action="store_true", help="export untrained weights (speed checks)")
    args = ap.parse_args()
    torch.set_num_threads(args.threads)
    torch.manual_seed(args.seed)
    hw = (args.height, args.width)
    model = PSPNetSmall(hw, bins=tuple(args.bins))
    print(f"PSPNetSmall {hw[0]}x{hw[1]}: {sum(p.numel() for p in model.parameters()) / 1e3:.0f} k parameters")
    if args.export_only:
        export(model, hw, Path(args.out))
        return
    if not args.train:
        sys.exit("train_segmenter: --train is required (or --export-only)")

    xs, y_train = load(args.train, hw, args.label_scale)
    x_train = normalise(xs)
    print(f"training frames: {len(x_train)} from {len(args.train)} sequences")
    val = None
    if args.val:
        xv, yv = load(args.val, hw, args.label_scale)
        val = (normalise(xv), yv)
        print(f"validation frames: {len(xv)} from {len(args.val)} sequences")
    weights = class_weights(y_train)
    print("class weights:", {CLASS_NAMES[i]: round(weights[i].item(), 2) for i in range(NUM_CLASSES) if weights[i] > 0})

    opt = torch.optim.AdamW(model.parameters(), lr=args.lr, weight_decay=1e-4)
    gen = torch.Generator().manual_seed(args.seed)
    steps_per_epoch = math.ceil(len(x_train) / args.batch)
    budget_s, start, step = args.minutes * 60.0, time.time(), 0
    est_total = None
    for epoch in range(args.epochs):
        perm = torch.randperm(len(x_train), generator=gen)
        loss_sum = 0.0
        for i in range(steps_per_epoch):
            idx = perm[i * args.batch:(i + 1) * args.batch]
            xb, yb = augment(x_train[idx].clone(), y_train[idx].clone(), gen)
            # cosine learning rate over the (estimated) total number of steps within the time budget
            elapsed = time.time() - start
            if est_total is None and step == 20:
                est_total = int(budget_s / (elapsed / 20))
            frac = min(step / est_total, 1.0) if est_total else 0.0
            for g in opt.param_groups:
                g["lr"] = args.lr * 0.5 * (1 + math.cos(math.pi * frac))
            logits = F.interpolate(model(xb), size=yb.shape[-2:], mode="bilinear", align_corners=False)
            loss = F.cross_entropy(logits, yb, weight=weights, ignore_index=0)
            opt.zero_grad()
            loss.backward()
            opt.step()
            loss_sum += loss.item()
            step += 1
        elapsed = time.time() - start
        msg = f"epoch {epoch + 1}: loss {loss_sum / steps_per_epoch:.3f}, {elapsed / 60:.1f} min"
        if val is not None and (epoch % 5 == 4 or elapsed > budget_s):
            msg += f", val mIoU {evaluate(model, *val)[0]:.3f}"
        print(msg, flush=True)
        if elapsed > budget_s:
            break
    if val is not None:
        m, per_class = evaluate(model, *val)
        print(f"final val mIoU {m:.4f} (PyTorch, labels at {args.label_scale}x the input size): {per_class}")
    export(model, hw, Path(args.out))
    torch.save(model.state_dict(), str(Path(args.out).with_suffix(".pt")))
    print(f"wrote {args.out} ({Path(args.out).stat().st_size / 1e6:.2f} MB)")


if __name__ == "__main__":
    main()
