#!/usr/bin/env python3
"""Builds the tiny ONNX models that tests/unit/semantics_onnx_test.cpp runs through OnnxSegmenter.

Run with Debian's Python (needs python3-onnx, python3-numpy):
    /usr/bin/python3 tools/seg_make_test_model.py tests/data/semantics

tiny_rgb.onnx      input [1,3,16,16] -> 1x1 conv -> logits [1,4,16,16]
tiny_rgb_s2.onnx   the same conv followed by a 2x2/stride-2 average pool -> logits [1,4,8,8]
tiny_flat.onnx     the same conv, flattened to [1,4,256]: a model whose output is not NCHW (an error)
Logits for a pixel with RGB values (r, g, b) in [0,1] (card: scale 1/255, rgb order, mean 0, std 1):
    wall = 10 r, floor = 10 g, chair = 10 b, spaceship = 2   (spaceship is not a project class -> "other")
so pure red -> wall, pure green -> floor, pure blue -> chair, black -> other, with exact softmax values.
"""
import sys
from pathlib import Path

import numpy as np

try:
    import onnx
    from onnx import TensorProto, helper, numpy_helper
except ImportError:
    sys.exit("seg_make_test_model: the onnx module is missing: scripts/setup.sh --with-training installs it (python3-onnx)")


def build(path: Path, stride2: bool, flat: bool = False) -> None:
    w = np.zeros((4, 3, 1, 1), np.float32)
    w[0, 0] = w[1, 1] = w[2, 2] = 10.0
    b = np.array([0, 0, 0, 2], np.float32)
    nodes = [helper.make_node("Conv", ["input", "W", "B"], ["conv" if stride2 or flat else "logits"], kernel_shape=[1, 1])]
    out_shape = [1, 4, 16, 16]
    inits = [numpy_helper.from_array(w, "W"), numpy_helper.from_array(b, "B")]
    if stride2:
        nodes.append(helper.make_node("AveragePool", ["conv"], ["logits"], kernel_shape=[2, 2], strides=[2, 2]))
        out_shape = [1, 4, 8, 8]
    if flat:
        nodes.append(helper.make_node("Reshape", ["conv", "shape"], ["logits"]))
        out_shape = [1, 4, 256]
        inits.append(numpy_helper.from_array(np.array(out_shape, np.int64), "shape"))
    graph = helper.make_graph(
        nodes, path.stem,
        [helper.make_tensor_value_info("input", TensorProto.FLOAT, [1, 3, 16, 16])],
        [helper.make_tensor_value_info("logits", TensorProto.FLOAT, out_shape)], inits)
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 11)], producer_name="s3m-tests")
    model.ir_version = 6
    onnx.checker.check_model(model)
    onnx.save(model, str(path))


def main() -> None:
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "tests/data/semantics")
    out.mkdir(parents=True, exist_ok=True)
    build(out / "tiny_rgb.onnx", stride2=False)
    build(out / "tiny_rgb_s2.onnx", stride2=True)
    build(out / "tiny_flat.onnx", stride2=False, flat=True)
    (out / "tiny_rgb.classes.txt").write_text("# output channel order of tiny_rgb*.onnx\nwall\nfloor\nchair\nspaceship\n")
    print("wrote", *sorted(p.name for p in out.iterdir()))


if __name__ == "__main__":
    main()
