#!/usr/bin/python3
"""policy_probe.py MODEL.pt INPUT: the Python twin of policy_probe.cpp.

Loads an exported policy with Python's torch.jit.load (Debian's python3-torch, nothing of rlt)
and prints its deterministic actions in policy_probe's format, so that policy_export_test can
hold the Python side to the same actions as rlt's own inference.

INPUT (whitespace separated):
  B M N                     rows, mask width (0 = call without a mask), observation count
  N lines: R d1 .. dR       shape of each observation without the batch dimension
  B rows of floats          each row the observations flattened and concatenated
  if M > 0: B rows of M     mask values (1 = allowed)
Output: "spec_json <json>", "format_version <n>", then per row "c1 .. cC | d1 .. dK".
"""
import sys

try:
    import torch
except ImportError:
    sys.exit("policy_probe.py: Python's torch is missing (Debian: apt-get install python3-torch)")


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: policy_probe.py MODEL.pt INPUT")
    with open(sys.argv[2]) as f:
        tokens = f.read().split()
    position = 0

    def take(count, kind):
        nonlocal position
        if position + count > len(tokens):
            sys.exit("policy_probe.py: input ended early")
        values = [kind(t) for t in tokens[position:position + count]]
        position += count
        return values

    rows, mask_width, count = take(3, int)
    shapes = []
    for _ in range(count):
        (rank,) = take(1, int)
        shapes.append(take(rank, int))
    sizes = [1] * count
    for i, shape in enumerate(shapes):
        for n in shape:
            sizes[i] *= n
    flat = torch.tensor(take(rows * sum(sizes), float), dtype=torch.float32).reshape(rows, -1)
    mask = None
    if mask_width > 0:
        mask = torch.tensor(take(rows * mask_width, float), dtype=torch.float32)
        mask = mask.reshape(rows, mask_width)

    # the rows split into the observation tensors, [rows, *shape] each
    observations = []
    offset = 0
    for shape, size in zip(shapes, sizes):
        observations.append(flat[:, offset:offset + size].reshape([rows] + shape).contiguous())
        offset += size

    module = torch.jit.load(sys.argv[1])
    module.eval()
    with torch.no_grad():
        continuous, discrete = module(observations, mask) if mask is not None else module(observations)

    lines = ["spec_json " + module.spec_json, "format_version %d" % module.format_version]
    for r in range(rows):
        c = "".join("%.9g " % v for v in continuous[r].tolist())
        d = "".join(" %d" % k for k in discrete[r].tolist())
        lines.append(c + "|" + d)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
