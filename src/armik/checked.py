"""Numbers an option takes (a seed, a configuration), checked: an ``OptionError`` naming the
option, the value and what it must be otherwise (``armik.options``, ``armik.problem.budget``,
the facades)."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from armik.errors import OptionError, listing


def numbers(value: object) -> np.ndarray:
    """``value`` as a float array, or [nan] for what is not numbers (a string, complex
    numbers, ragged lists): the callers' checks then refuse it."""
    try:
        if isinstance(value, (str, bytes)) or np.iscomplexobj(value):  # type: ignore[arg-type]
            raise TypeError
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return np.array([np.nan])
    except OverflowError:  # an int beyond a float's range: not finite, as the checks say
        return np.array([np.inf])


def number(key: str, value: object) -> float:
    """``value`` as a finite float (not a bool or a string)."""
    if isinstance(value, (str, bytes, bool, np.bool_)):
        raise OptionError(f"{key} must be a number, got {value!r}", option=key, value=value)
    try:
        out = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise OptionError(
            f"{key} must be a number, got {value!r}", option=key, value=value
        ) from None
    except OverflowError:  # an int beyond a float's range
        out = math.inf
    if not math.isfinite(out):
        raise OptionError(f"{key} must be finite, got {value!r}", option=key, value=value)
    return out


def positive(key: str, value: object, most: float, unit: str) -> float:
    """``value`` as a float in (0, ``most``] (``unit``: how the error names it)."""
    out = number(key, value)
    if out <= 0:
        raise OptionError(f"{key} must be > 0, got {value!r}", option=key, value=value)
    if out > most:
        hint = " (iteration_budget gives a budget that is not time)" if key == "timeout" else ""
        raise OptionError(
            f"{key} must be at most {most:g} {unit}, got {value!r}{hint}",
            option=key,
            value=value,
        )
    return out


def integer(key: str, value: object, minimum: int, maximum: int | None = None) -> int:
    """``value`` as an int in [``minimum``, ``maximum``] (not a bool or a float)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise OptionError(
            f"{key} must be an integer >= {minimum}, got {value!r}", option=key, value=value
        )
    if value < minimum:
        raise OptionError(f"{key} must be >= {minimum}, got {value!r}", option=key, value=value)
    if maximum is not None and value > maximum:
        raise OptionError(
            f"{key} must be at most {maximum}, got {value!r}: give a smaller value",
            option=key,
            value=value,
        )
    return int(value)


MOST_SEED = 2**32 - 1  # numpy's legacy seeds (scipy's ``random_state``): [0, 2**32 - 1]


def sampling_seed(
    key: str, value: object
) -> int | np.random.Generator | np.random.RandomState | None:
    """``value`` as a sampling seed numpy takes as ``random_state``: a whole number in
    [0, 2**32 - 1] (the CLI's ``--seed`` words), or None or a numpy generator as given."""
    if value is None or isinstance(value, (np.random.Generator, np.random.RandomState)):
        return value
    if isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_)):
        if 0 <= value <= MOST_SEED:
            return int(value)
    raise OptionError(
        f"{key} must be a whole number in [0, {MOST_SEED}] (a sampling seed), got {value!r}",
        option=key,
        value=value,
    )


def generator(key: str, value: object) -> np.random.Generator:
    """``value`` (a ``numpy.random.Generator``, a seed >= 0 or None) as a generator."""
    try:
        if isinstance(value, (str, bytes, float)):
            raise TypeError
        return np.random.default_rng(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise OptionError(
            f"{key} must be a numpy.random.Generator, a whole-number seed >= 0 or None, "
            f"got {value!r}",
            option=key,
            value=value,
        ) from None


def configuration(
    key: str, value: object, joint_names: Sequence[str], finite: bool = True
) -> np.ndarray:
    """``value`` as one configuration, a float array of one value per joint of
    ``joint_names`` (rad or m); with ``finite`` False a NaN or infinity passes (a limits
    check says it is outside)."""
    dof = len(joint_names)
    try:
        if isinstance(value, (str, bytes)) or np.iscomplexobj(value):  # type: ignore[arg-type]
            raise TypeError  # never drop an imaginary part silently
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise OptionError(
            f"{key} must be {dof} numbers (one per joint), got {value!r}", option=key, value=value
        ) from None
    except OverflowError:  # an int beyond a float's range
        raise OptionError(
            f"{key} must be {dof} finite numbers (one per joint): a value of {value!r} is too "
            "large for a float",
            option=key,
            value=value,
        ) from None
    if arr.shape != (dof,):
        several = ""
        if arr.ndim == 2 and arr.shape[1] == dof:
            several = f"; for {arr.shape[0]} configurations, ask one row at a time"
        raise OptionError(
            f"{key} must have {dof} values (one per joint: {', '.join(joint_names)}), got "
            f"shape {arr.shape}{several}",
            option=key,
            value=value,
        )
    if finite and not np.isfinite(arr).all():
        bad = [joint_names[int(i)] for i in np.flatnonzero(~np.isfinite(arr))]
        raise OptionError(
            f"{key} must be finite, got {arr.tolist()}: not finite at {listing(bad)}",
            option=key,
            value=value,
        )
    return arr
