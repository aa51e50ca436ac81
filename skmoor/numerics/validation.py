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
