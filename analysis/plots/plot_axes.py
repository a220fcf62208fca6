"""Axis choices shared by the plot scripts (imported from the scripts' own directory)."""
import numpy as np


def spans_a_decade(arrays):
    """Log axis: every finite value positive and the largest at least 10 x the smallest (over a
    narrower range log ticks are unreadable; a value <= 0 cannot be drawn on a log axis)."""
    v = np.concatenate([np.ravel(np.asarray(a, dtype=float)) for a in arrays])
    v = v[np.isfinite(v)]
    return len(v) > 1 and v.min() > 0 and v.max() >= 10 * v.min()
