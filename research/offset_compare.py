"""offset_compare: how far an image moved against the same scene rendered at the origin: the
change of its mean, and the share of lit pixels (luminance above 0.1) that moved by more than 5%.
    offset_compare.py AT_ORIGIN.exr MOVED.exr"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
import imagediff  # noqa: E402

near = imagediff.read_exr(sys.argv[1]).mean(-1)
far = imagediff.read_exr(sys.argv[2]).mean(-1)
lit = near > 0.1
moved = np.abs(far - near) / np.maximum(near, 1e-6) > 0.05
print(f"mean {100 * (far.mean() / near.mean() - 1):+.3f}%, "
      f"{100 * moved[lit].mean():.2f}% of {lit.sum()} lit pixels moved by more than 5%")
