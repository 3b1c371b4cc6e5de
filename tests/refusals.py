"""The hostile-input tests' one assertion: a call refused with exactly the uavcov error expected."""

from __future__ import annotations

from typing import Any

import pytest


def refused(error: type[Exception], words: str, call: Any, *args: Any, **kwargs: Any) -> None:
    """``call`` raises exactly ``error`` (a uavcov error) with ``words`` in its message."""
    with pytest.raises(error, match=words) as caught:
        call(*args, **kwargs)
    assert type(caught.value) is error, repr(caught.value)
