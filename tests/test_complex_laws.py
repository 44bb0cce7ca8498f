"""SIMPCOMP laws (spec/simpcomp_laws.py) on random histories, dimensions 1–4, every structure.

Hypothesis draws a history of operations over a small pool of vertices (so
simplices collide, reappear and get reversed).  Each step runs the law of its
operation against a model (oriented key → datum); every version is kept and,
at the end, every one is rechecked against the model it had when it was made
(persistence) and by :func:`check_complex` (the paper's conditions 1–3 and
the representation's consistency).
"""

from __future__ import annotations

from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from complex_helpers import STRUCTURE_IDS, STRUCTURES, Make, fresh
from persistri.impl.complex.checks import check_complex
from persistri.spec import simpcomp_laws as laws
from persistri.spec.simpcomp_laws import Model, oriented_key, representative

OPS = ["add", "add", "add", "rem", "update", "find", "grep", "inverse", "readd"]

history_steps = st.lists(
    st.tuples(st.sampled_from(OPS), st.randoms(use_true_random=False), st.integers(0, 1000)),
    max_size=18,
)


def run_history(make: Make, n: int, steps: list[tuple[str, Any, int]]) -> None:
    C = make(n)
    S = C.Simplex
    pool = fresh(n + 3)
    c = laws.law_new(C, n)
    model: Model = {}
    history: list[tuple[Any, Model]] = [(c, model)]
    for op, rng, x in steps:
        s = tuple(rng.sample(pool, n + 1))
        key = oriented_key(S, s)
        held = key in model or oriented_key(S, S.flip(s)) in model
        if op == "add" or (op == "readd" and not model):
            if held:
                laws.law_add_present(C, c, n, model, s, x)
            else:
                c, model = laws.law_add(C, c, n, model, s, x)
        elif op == "readd":
            # the reverse of a held simplex, in some order of that reverse orientation
            t = representative(S, rng.choice(sorted(model, key=repr)))
            laws.law_add_present(C, c, n, model, S.flip(t), x)
            laws.law_add_present(C, c, n, model, t, x)
        elif op in ("rem", "update"):
            if not model:
                laws.law_rem_absent(C, c, n, model, s)
                continue
            t = representative(S, rng.choice(sorted(model, key=repr)))
            if len(t) >= 3:  # another order of the same orientation
                t = (t[1], t[2], t[0]) + t[3:]
            if op == "rem":
                if n >= 1:
                    laws.law_rem_absent(C, c, n, model, S.flip(t))
                c, model = laws.law_rem(C, c, n, model, t)
            else:
                c, model = laws.law_update(C, c, n, model, t, lambda d: d + 1)
        elif op == "find":
            laws.law_find(C, c, n, model, s[:n])
        elif op == "grep":
            d = x % (n + 1)
            k = (x // 7) % (n + 1)
            laws.law_grep(C, c, n, model, d, s[: k + 1])
        elif op == "inverse":
            if not held:
                laws.law_add_rem_inverse(C, c, n, model, s, x)
        history.append((c, model))
    laws.law_persistence(C, n, history)
    for version, _ in history:
        check_complex(version)


@pytest.mark.parametrize("n", [1, 2, 3, 4])
@pytest.mark.parametrize("make", [m for _, m in STRUCTURES], ids=STRUCTURE_IDS)
@settings(max_examples=max(3, settings.default.max_examples // 6))
@given(steps=history_steps)
def test_random_histories_keep_every_law(make: Make, n: int, steps: list[tuple[str, Any, int]]) -> None:
    run_history(make, n, steps)


@pytest.mark.parametrize("n", [2, 3])
@settings(max_examples=max(8, settings.default.max_examples // 4))
@given(steps=st.lists(st.tuples(st.sampled_from(OPS), st.randoms(use_true_random=False), st.integers(0, 1000)),
                      min_size=10, max_size=40))
def test_long_histories_red_black(n: int, steps: list[tuple[str, Any, int]]) -> None:
    """Longer histories on the structure the algorithms use (the hypothesis profile sets how many)."""
    make = dict(STRUCTURES).get("red_black", STRUCTURES[0][1])
    run_history(make, n, steps)


@pytest.mark.parametrize("make", [m for _, m in STRUCTURES], ids=STRUCTURE_IDS)
@pytest.mark.parametrize("n", [2, 3, 4])
def test_full_star_and_grep_everywhere(make: Make, n: int) -> None:
    """Every n-simplex on n+2 vertices, half of them reversed: grep and find for every face, every d."""
    from itertools import combinations

    C = make(n)
    S = C.Simplex
    pool = fresh(n + 2)
    c = C.new(n)
    model: dict[Any, Any] = {}
    for i, t in enumerate(combinations(pool, n + 1)):
        t = S.flip(t) if i % 2 else t
        c, model = laws.law_add(C, c, n, model, t, i, recheck=False)
    for k in range(n + 1):
        for f in combinations(pool, k + 1):
            for g in (f, S.flip(f)):
                for d in range(n + 1):
                    laws.law_grep(C, c, n, model, d, g)
                if k == n - 1:
                    laws.law_find(C, c, n, model, g)
    check_complex(c)
