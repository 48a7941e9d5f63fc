"""Hostile and extreme input from Python: every value the grading rule or
the validation contract cannot read is an exception naming it, and nothing
hangs."""

import math
import time

import numpy as np
import pytest

import granular_automata as ga


def test_grade_of_a_huge_run_count_returns_at_once():
    # the coverage factor cost grew with n: 3.2 s at 1e8, a hang at 2^63
    start = time.monotonic()
    for n in (10**8, 2**63, 2**64 - 1):
        assert ga.grade(1.0, 0.1, n, target=1.0, margin=0.1) == "undecided"
        assert ga.grade(1.0, 0.01, n, target=1.0, margin=0.1) == "reproduced"
    assert time.monotonic() - start < 1.0


@pytest.mark.parametrize(
    "args, kwargs, needle",
    [
        ((math.nan, 0.1, 10), dict(target=1.0, margin=0.1), "mean = NaN"),
        ((1.0, -0.1, 10), dict(target=1.0, margin=0.1), "se = -0.1"),
        ((1.0, math.nan, 10), dict(target=1.0, margin=0.1), "se = NaN"),
        ((1.0, 0.1, 0), dict(target=1.0, margin=0.1), "n = 0"),
        ((1.0, 0.1, 10), dict(target=1.0, margin=-0.1), "margin = -0.1"),
        ((1.0, 0.1, 10), dict(target=math.inf, margin=0.1), "target = inf"),
        ((1.0, 0.1, 10), dict(above=math.inf), "above = inf"),
        ((1.0, 0.1, 10), dict(above=math.nan), "above = NaN"),
        ((1.0, 0.1, 10), dict(below=-math.inf), "below = -inf"),
    ],
)
def test_grade_refuses_what_the_rule_cannot_read(args, kwargs, needle):
    # each was graded "undecided" without a word
    with pytest.raises(ValueError, match=needle.replace("(", r"\(")):
        ga.grade(*args, **kwargs)


def test_grade_of_one_run_without_a_spread_is_undecided():
    assert ga.grade(1.0, math.nan, 1, target=1.0, margin=0.1) == "undecided"


def test_pipe_run_refuses_more_steps_than_any_binary():
    pipe = ga.Pipe(width=3, length=20, bin=10, seed=1)
    with pytest.raises(ValueError, match="steps = 18446744073709551615"):
        pipe.run(2**64 - 1)
    assert pipe.time == 0


def wrapped(state_of):
    """A candidate: the reference engine, its state() passed through
    state_of."""

    class Engine:
        def __init__(self, params, rules, seed):
            self.pipe = ga.Pipe(**params, rules=rules, seed=seed)

        def step(self):
            self.pipe.run(1)

        def state(self):
            return state_of(self.pipe.state())

        def set_state(self, a):
            self.pipe.set_state(a)

        def bin_counts(self):
            return self.pipe.bin_counts()

        def channel_counts(self):
            return self.pipe.channel_counts()

        def flux(self):
            return self.pipe.flux()

    return Engine


def test_validate_refuses_a_state_byte_above_seven_bits():
    def with_255(s):
        s = np.array(s, dtype=np.uint8)
        s[0, 0] = 255
        return s

    with pytest.raises(ValueError, match="255 at site"):
        ga.validate(wrapped(with_255), level="1")


def test_validate_names_a_factory_that_returns_none():
    # it said "'NoneType' object has no attribute 'set_state'"
    with pytest.raises(TypeError, match="factory.*returned None"):
        ga.validate(lambda params, rules, seed: None, level="1")
