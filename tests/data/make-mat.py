#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""MATLAB v5 test files for the capture reader, written by Debian's
python3-scipy (scipy.io.savemat, uncompressed unless named so):

    cd tests/data && /usr/bin/python3 make-mat.py

small.mat             x (1x5 double), m (5x2 int16), t (5x1 double), s
                      (scalar), label (char), z (complex, skipped)
small-compressed.mat  the same, zlib-compressed (refused with a message)
bearing.mat           acc: samples/bearing-outer.csv's column (doubles),
                      RPM: 1797 (a scalar, left out)
"""
import numpy as np
import scipy.io as sio

small = {
    "x": np.array([[1.5, -2.25, 3.0, 4e10, 5e-7]]),
    "m": np.array([[1, -2], [3, -4], [5, -6], [7, -8], [32767, -32768]],
                  dtype=np.int16),
    "t": np.array([0.0, 0.1, 0.2, 0.3, 0.4]),
    "s": 42.0,
    "label": "not a channel",
    "z": np.array([1 + 2j, 3, 4, 5, 6]),
}
sio.savemat("small.mat", small, oned_as="column")
sio.savemat("small-compressed.mat", small, oned_as="column",
            do_compression=True)
acc = np.loadtxt("../../samples/bearing-outer.csv", comments="#", skiprows=3)
sio.savemat("bearing.mat", {"acc": acc, "RPM": 1797.0}, oned_as="column")
