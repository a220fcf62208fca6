"""Axis choices shared by the plot scripts (imported from the scripts' own directory)."""
import numpy as np


def spans_a_decade(arrays):
    """Log axis: every finite value positive and the largest at least 10 x the smallest (over a
    narrower range log ticks are unreadable; a value <= 0 cannot be drawn on a log axis)."""
    v = np.concatenate([np.ravel(np.asarray(a, dtype=float)) for a in arrays])
    v = v[np.isfinite(v)]
    return len(v) > 1 and v.min() > 0 and v.max() >= 10 * v.min()


def label_rate_step_axes(axes, friction_label="mu = tau / sigma_yy"):
    """The row of a run with a step in the shear rate: mu, phi and T (log) against gamma, the step
    marked dotted (plot_transient_dem.py, plot_transient_pair.py)."""
    for ax, label in zip(axes, (friction_label, "solid fraction phi", "T (m^2/s^2)")):
        ax.set_xlabel("shear strain gamma   (dotted: the step in the shear rate)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    if len(axes) > 2:
        axes[2].set_yscale("log")
