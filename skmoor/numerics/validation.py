"""Input checks whose errors name the field and the reason."""
import numpy as np


def check_finite(name: str, value) -> None:
    """Raise ValueError if ``value`` holds NaN or inf."""
    arr = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name}: must be finite, got {value!r}")


def check_positive(name: str, value) -> None:
    """Raise ValueError unless ``value`` is finite and > 0."""
    check_finite(name, value)
    if np.any(np.asarray(value, dtype=float) <= 0):
        raise ValueError(f"{name}: must be positive, got {value!r}")


def user_stacklevel() -> int:
    """The ``stacklevel`` for a ``warnings.warn`` in the function that calls this one that
    points at the first caller outside skmoor (the user's script, not skmoor's source)."""
    import os
    import sys

    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__))) + os.sep
    frame, level = sys._getframe(1), 1
    while frame is not None and (os.path.abspath(frame.f_code.co_filename).startswith(package)
                                 or frame.f_code.co_filename.startswith("<")):
        frame, level = frame.f_back, level + 1
    return level
