"""``progress=`` as a library caller passes it: a NumPy boolean is a bool, and a refusal names the real type.

``progress=np.bool_(True)`` used to be refused as "not bool" (NumPy's bool type is also called ``bool``).
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from persistri.impl.progress import ProgressBar, progress_callback


def test_a_numpy_bool_is_a_bool() -> None:
    bar = progress_callback(np.bool_(True), "t", 10)
    assert isinstance(bar, ProgressBar)
    bar.close()
    assert progress_callback(np.bool_(False), "t", 10) is None


@pytest.mark.parametrize(
    ("value", "name"), [(1, "int"), ("yes", "str"), (Fraction(1), "fractions.Fraction"), (np.int64(1), "numpy.int64")]
)
def test_a_refusal_names_the_type_with_its_module(value: object, name: str) -> None:
    with pytest.raises(TypeError, match=rf"^progress must be a bool or a callable, not {name}$"):
        progress_callback(value, "t", 10)  # type: ignore[arg-type]
