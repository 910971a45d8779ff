"""Per-pixel tests of two 8-bit values as table look-ups (cv2.LUT), with exactly the results of
the tests themselves.  Pure numpy, no ROS.

A test such as g - max(r, b) >= 0.5 g (obstacles.colour_masks) or grey >= 0.55 bright
(lane_measurement.line_mask) costs a conversion and a floating-point multiply per pixel.  For
each value of one operand, the values of the other that pass form a threshold (a >= t[b], or
a <= t[b]): the test is evaluated once for all 256 x 256 pairs of values (numpy, the operands'
types as the caller's), the thresholds are read off, and a frame only looks them up.  A test
that is not of that form gives no table (the caller evaluates it per pixel as before).
"""
import numpy as np

VALUES = np.arange(256, dtype=np.int16)


def threshold_table(test, upward: bool):
    """For test(a, b), boolean arrays from int16 arrays of values 0..255 (cast as the caller's
    per-pixel test casts its operands), the int16 table t of 256 entries such that test(a, b) ==
    (a >= t[b]) when upward (t[b] = 256: never), else test(a, b) == (a <= t[b]) (t[b] = -1:
    never), for every pair a, b in 0..255; None when the test is not of that form."""
    a, b = np.meshgrid(VALUES, VALUES, indexing="ij")
    passes = np.asarray(test(a, b), dtype=bool)
    if passes.shape != a.shape:
        return None
    some = passes.any(axis=0)
    if upward:
        table = np.where(some, passes.argmax(axis=0), 256).astype(np.int16)
        same = np.array_equal(passes, a >= table[None, :])
    else:
        table = np.where(some, 255 - passes[::-1].argmax(axis=0), -1).astype(np.int16)
        same = np.array_equal(passes, a <= table[None, :])
    return table if same else None


class TableCache:
    """Tables made by make(*key) once per key (None when a key is not hashable: made each time)."""

    def __init__(self, make):
        self.make = make
        self.tables = {}

    def get(self, *key):
        try:
            return self.tables[key]
        except KeyError:
            tables = self.tables[key] = self.make(*key)
            return tables
        except TypeError:  # not hashable
            return self.make(*key)
