"""Bad input gets a clear error: every public entry point of the foundation, and the helpers.

Every message is one sentence: "`name` must be <rule>; got <value> [at index i]."
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from presliding import PIFriction, PIOperator, PIState, play, stop
from presliding._validation import (
    as_choice,
    as_count,
    as_nonnegative_scalar,
    as_parameter_vector,
    as_positive_scalar,
    as_real_scalar,
    as_real_vector,
    as_signal,
    as_state_vector,
    check_same_length,
    fmt,
)
from presliding.signals import piecewise_linear

WORDING = re.compile(r"^`(?P<name>\w+)`[^;]* must [^;]+; got [^;]+\.$")


def assert_rejects(call, exc: type[Exception], name: str) -> str:
    """`call()` raises `exc` with one sentence naming `name` in the house style."""
    with pytest.raises(exc) as info:
        call()
    assert type(info.value) is exc
    message = str(info.value)
    match = WORDING.match(message)
    assert match, f"message not in the house style: {message!r}"
    assert match.group("name") == name or f"`{name}`" in message, message
    assert message.count(". ") == 0 or "(" in message, f"more than one sentence: {message!r}"
    return message


# ----------------------------------------------------------------------------- bad values

BAD_PARAMETER_VALUES = [
    pytest.param(-3.0, ValueError, "must be positive; got -3.0", id="negative"),
    pytest.param(0.0, ValueError, "must be positive; got 0.0", id="zero"),
    pytest.param(np.nan, ValueError, "must be finite; got nan", id="nan"),
    pytest.param(np.inf, ValueError, "must be finite; got inf", id="inf"),
    pytest.param("1.0", TypeError, "real number", id="str"),
    pytest.param(None, TypeError, "real number", id="None"),
    pytest.param(1j, TypeError, "real number", id="complex"),
    pytest.param(True, TypeError, "real number", id="bool"),
    pytest.param([[1.0, 2.0]], ValueError, "one-dimensional", id="2d"),
]

# thresholds of play, stop and PIOperator may be 0 (the identity play)
BAD_THRESHOLD_VALUES = [
    pytest.param(-3.0, ValueError, "must be nonnegative; got -3.0", id="negative"),
    *(p for p in BAD_PARAMETER_VALUES if p.id not in ("negative", "zero")),
]

BAD_SIGNALS = [
    pytest.param([0.0, np.nan, 1.0], ValueError, "must be finite; got nan at index 1.", id="nan"),
    pytest.param([0.0, 1.0, -np.inf], ValueError, "must be finite; got -inf at index 2.", id="inf"),
    pytest.param([], ValueError, "must not be empty; got 0 samples.", id="empty"),
    pytest.param([[0.0, 1.0]], ValueError, "one-dimensional", id="2d"),
    pytest.param("0 1 2", TypeError, "real number", id="str"),
    pytest.param(None, TypeError, "real number", id="None"),
    pytest.param([0j, 1j], TypeError, "complex", id="complex"),
    pytest.param([True, False], TypeError, "bool", id="bool"),
]

BAD_SCALARS = [
    pytest.param(np.nan, ValueError, "must be finite; got nan.", id="nan"),
    pytest.param(np.inf, ValueError, "must be finite; got inf.", id="inf"),
    pytest.param("0.0", TypeError, "must be a real number; got '0.0'.", id="str"),
    pytest.param(None, TypeError, "must be a real number; got None.", id="None"),
    pytest.param(1 + 0j, TypeError, "must be a real number; got (1+0j).", id="complex"),
    pytest.param(True, TypeError, "must be a real number; got True.", id="bool"),
    pytest.param([1.0, 2.0], TypeError, "must be a real number; got [1.0, 2.0].", id="list"),
]


def _vector(value, n=2):
    """A bad value placed at index 1 of an otherwise good vector (scalars), or as is."""
    if np.ndim(value) == 0 and isinstance(value, float):
        return [1.0, value][:n] if n > 1 else [value]
    return value


def _at_index_1(value, message: str, text: str) -> None:
    if isinstance(value, float):
        assert message.endswith(f"{text} at index 1."), message
    else:
        assert text in message, message


# ----------------------------------------------------------------------------- operators


@pytest.mark.parametrize(("value", "exc", "text"), BAD_THRESHOLD_VALUES)
def test_play_and_stop_reject_bad_thresholds(value, exc, text):
    for fn in (play, stop):
        message = assert_rejects(lambda fn=fn: fn([0.0, 1.0], _vector(value)), exc, "threshold")
        _at_index_1(value, message, text)


@pytest.mark.parametrize(("value", "exc", "text"), BAD_SIGNALS)
def test_play_and_stop_reject_bad_signals(value, exc, text):
    for fn in (play, stop):
        assert text in assert_rejects(lambda fn=fn: fn(value, 0.1), exc, "y")


def test_play_rejects_bad_initial_state():
    message = assert_rejects(lambda: play([0.0, 1.0], [0.1, 0.2], [0.0]), ValueError, "initial")
    assert message.endswith("got shape (1,).")
    message = assert_rejects(
        lambda: play([0.0, 1.0], [0.1, 0.2], [0.0, 0.5]), ValueError, "initial"
    )
    assert message.endswith("at index 1.")
    assert_rejects(lambda: play([0.0], 0.1, np.nan), ValueError, "initial")
    assert_rejects(lambda: stop([0.0], 0.1, "0"), TypeError, "initial")
    assert_rejects(lambda: stop([0.0], 0.1, [[0.0]]), ValueError, "initial")
    # within rounding of the threshold is accepted
    play([1e3], 1e-3, 1e3 - 1e-3)


@pytest.mark.parametrize(("value", "exc", "text"), BAD_THRESHOLD_VALUES)
def test_pi_operator_rejects_bad_thresholds(value, exc, text):
    message = assert_rejects(
        lambda: PIOperator(_vector(value), [1.0, 1.0][: len(np.atleast_1d(_vector(value)))]),
        exc,
        "threshold",
    )
    _at_index_1(value, message, text)


@pytest.mark.parametrize(
    ("value", "exc"),
    [
        pytest.param([1.0, np.nan], ValueError, id="nan"),
        pytest.param([1.0, np.inf], ValueError, id="inf"),
        pytest.param(["a", "b"], TypeError, id="str"),
        pytest.param(None, TypeError, id="None"),
        pytest.param([1j, 1.0], TypeError, id="complex"),
        pytest.param([True, False], TypeError, id="bool"),
        pytest.param([[1.0, 2.0]], ValueError, id="2d"),
    ],
)
def test_pi_operator_rejects_bad_weights(value, exc):
    assert_rejects(lambda: PIOperator([0.1, 0.2], value), exc, "weight")


def test_pi_operator_rejects_mismatched_lengths_and_empty_banks():
    message = assert_rejects(lambda: PIOperator([0.1, 0.2], [1.0]), ValueError, "weight")
    assert message.endswith("same length as `threshold` (2); got 1.")
    assert_rejects(lambda: PIOperator([], []), ValueError, "threshold")


@pytest.mark.parametrize(("value", "exc", "text"), BAD_SIGNALS)
def test_pi_operator_apply_rejects_bad_signals(value, exc, text):
    op = PIOperator([0.1, 0.2], [1.0, 2.0])
    assert text in assert_rejects(lambda: op.apply(value), exc, "y")


def test_pi_operator_apply_rejects_bad_states():
    op = PIOperator([0.1, 0.2], [1.0, 2.0])
    message = assert_rejects(lambda: op.apply([0.0], PIState(0.0, [0.0])), ValueError, "state")
    assert message.endswith("got 1.")
    message = assert_rejects(lambda: op.apply([0.0], PIState(0.0, [0.0, 0.3])), ValueError, "state")
    assert message.endswith("at index 1.")
    assert_rejects(lambda: op.apply([0.0], [0.0, 0.0]), TypeError, "state")
    assert_rejects(lambda: op.apply([0.0], "relaxed"), TypeError, "state")


@pytest.mark.parametrize(("value", "exc", "text"), BAD_SCALARS)
def test_pi_state_rejects_bad_scalars(value, exc, text):
    assert assert_rejects(lambda: PIState(value, [0.0]), exc, "last_input").endswith(text)
    assert assert_rejects(lambda: PIState(0.0, [0.0], value), exc, "direction").endswith(text)
    assert assert_rejects(lambda: PIState.relaxed(value, 2), exc, "position").endswith(text)
    assert assert_rejects(lambda: PIState.saturated(0.0, [0.1], value), exc, "direction").endswith(
        text
    )


def test_pi_state_rejects_bad_values():
    assert_rejects(lambda: PIState(0.0, [0.0], 2), ValueError, "direction")
    assert_rejects(lambda: PIState(0.0, [0.0], 0.5), ValueError, "direction")
    assert_rejects(lambda: PIState.saturated(0.0, [0.1], 0), ValueError, "direction")
    assert_rejects(lambda: PIState(0.0, 0.0), ValueError, "play")
    assert_rejects(lambda: PIState(0.0, [[0.0]]), ValueError, "play")
    assert_rejects(lambda: PIState(0.0, [np.nan]), ValueError, "play")
    assert_rejects(lambda: PIState(0.0, "0"), TypeError, "play")
    assert_rejects(lambda: PIState(0.0, None), TypeError, "play")
    assert_rejects(lambda: PIState(0.0, [1j]), TypeError, "play")
    assert_rejects(lambda: PIState.relaxed(0.0, -1), ValueError, "n_elements")
    assert_rejects(lambda: PIState.relaxed(0.0, 2.0), TypeError, "n_elements")
    assert_rejects(lambda: PIState.relaxed(0.0, True), TypeError, "n_elements")
    assert_rejects(lambda: PIState.saturated(0.0, [0.1, -0.1], 1), ValueError, "threshold")


# ----------------------------------------------------------------------------- friction


@pytest.mark.parametrize("name", ["stiffness", "breakaway", "threshold"])
@pytest.mark.parametrize(("value", "exc", "text"), BAD_PARAMETER_VALUES)
def test_friction_rejects_bad_element_parameters(name, value, exc, text):
    good = {
        "stiffness": [10.0, 4.0],
        "breakaway" if name != "threshold" else "threshold": [1.0, 1.0],
    }
    good[name] = _vector(value)
    if value is None and name != "stiffness":  # None is "not given"
        text = "must be given, not both; got neither"
    message = assert_rejects(lambda: PIFriction(0.5, **good), exc, name)
    _at_index_1(value, message, text)


@pytest.mark.parametrize(("value", "exc", "text"), BAD_SCALARS)
def test_friction_rejects_bad_coulomb_types(value, exc, text):
    assert assert_rejects(lambda: PIFriction(value, [1.0], [1.0]), exc, "coulomb").endswith(text)


def test_friction_rejects_negative_coulomb():
    message = assert_rejects(lambda: PIFriction(-0.5, [1.0], [1.0]), ValueError, "coulomb")
    assert message == "`coulomb` must be nonnegative; got -0.5."


def test_friction_rejects_inconsistent_construction():
    message = assert_rejects(lambda: PIFriction(0.5, [1.0, 2.0], [1.0]), ValueError, "breakaway")
    assert message.endswith("same length as `stiffness` (2); got 1.")
    assert_rejects(lambda: PIFriction(0.5, [1.0], threshold=[1.0, 2.0]), ValueError, "threshold")
    assert_rejects(lambda: PIFriction(0.5, [1.0], [1.0], threshold=[1.0]), TypeError, "breakaway")
    assert_rejects(lambda: PIFriction(0.5, [1.0]), TypeError, "breakaway")
    assert_rejects(lambda: PIFriction(0.0), ValueError, "coulomb")
    assert_rejects(lambda: PIFriction(0.0, [], []), ValueError, "coulomb")
    # r = c / k overflows or underflows: reported, never a silent inf or 0
    assert_rejects(lambda: PIFriction(0.0, [1e-300], [1e300]), ValueError, "breakaway")
    assert_rejects(lambda: PIFriction(0.0, [1e300], [1e-300]), ValueError, "breakaway")
    assert_rejects(lambda: PIFriction(0.0, [1e300], threshold=[1e300]), ValueError, "threshold")


@pytest.mark.parametrize(("value", "exc", "text"), BAD_SIGNALS)
def test_friction_methods_reject_bad_displacements(value, exc, text):
    model = PIFriction(0.5, [10.0, 4.0], [1.0, 1.0])
    for method in (model.force, model.elastic_force, model.virgin_curve):
        message = assert_rejects(lambda m=method: m(value), exc, "displacement")
        assert text in message


def test_friction_methods_reject_bad_states_and_flags():
    model = PIFriction(0.5, [10.0, 4.0], [1.0, 1.0])
    for method in (model.force, model.elastic_force):
        assert_rejects(lambda m=method: m([0.0], PIState(0.0, [0.0])), ValueError, "state")
        assert_rejects(lambda m=method: m([0.0], PIState(0.0, [0.0, 0.3])), ValueError, "state")
        assert_rejects(lambda m=method: m([0.0], 0.0), TypeError, "state")
    assert_rejects(lambda: model.virgin_curve(0.1, elastic_only="no"), TypeError, "elastic_only")
    assert_rejects(lambda: model.saturated_state(0.0, 0), ValueError, "direction")
    assert_rejects(lambda: PIFriction(1.0).saturated_state(0.0, 0), ValueError, "direction")
    assert_rejects(lambda: model.saturated_state(np.nan, 1), ValueError, "position")
    assert_rejects(lambda: model.relaxed_state("0"), TypeError, "position")


# ----------------------------------------------------------------------------- signals


@pytest.mark.parametrize(("value", "exc", "text"), BAD_SIGNALS)
def test_piecewise_linear_rejects_bad_turning_points(value, exc, text):
    assert_rejects(lambda: piecewise_linear(value, 0.1), exc, "turning_points")


@pytest.mark.parametrize(
    ("value", "exc"),
    [(0.0, ValueError), (-0.1, ValueError), (np.nan, ValueError), (np.inf, ValueError)]
    + [(v, TypeError) for v in ("0.1", None, 0.1j, True)],
)
def test_piecewise_linear_rejects_bad_steps(value, exc):
    assert_rejects(lambda: piecewise_linear([0.0, 1.0], value), exc, "step")


def test_piecewise_linear_needs_two_turning_points():
    message = assert_rejects(lambda: piecewise_linear([0.0], 0.1), ValueError, "turning_points")
    assert message.endswith("got 1 samples.")


# ----------------------------------------------------------------------------- the helpers


def test_helpers_return_clean_float64_arrays():
    src = [1, 2, 3]
    for helper in (as_parameter_vector, as_real_vector):
        out = helper("x", src)
        assert out.dtype == np.float64
        assert out.flags.c_contiguous
        assert not out.flags.writeable
    assert as_parameter_vector("x", 2).shape == (1,)
    assert as_parameter_vector("x", [0.0, 1.0], positive=False).tolist() == [0.0, 1.0]
    assert as_parameter_vector("x", [], allow_empty=True).shape == (0,)
    assert as_real_vector("x", [-1.0, 0.0]).tolist() == [-1.0, 0.0]
    signal = as_signal("y", np.arange(6.0).reshape(2, 3)[:, 0])  # strided view
    assert signal.flags.c_contiguous and signal.tolist() == [0.0, 3.0]
    assert as_state_vector("x", 0.5, 3).tolist() == [0.5, 0.5, 0.5]
    assert as_real_scalar("x", np.float32(1.5)) == 1.5
    assert as_positive_scalar("x", 2) == 2.0
    assert as_nonnegative_scalar("x", 0) == 0.0
    assert as_count("n", np.int64(3)) == 3
    assert as_choice("method", "a", ("a", "b")) == "a"
    check_same_length(a=np.zeros(2), b=[1, 2])


def test_helpers_do_not_alias_the_input():
    src = np.array([1.0, 2.0])
    out = as_state_vector("x", src, 2)
    out[0] = 5.0
    assert src[0] == 1.0


def test_helper_messages():
    cases = [
        (
            lambda: as_parameter_vector("stiffness", [1.0, -3.0]),
            ValueError,
            "stiffness",
            "`stiffness` must be positive; got -3.0 at index 1.",
        ),
        (
            lambda: as_parameter_vector("c", [1.0, -3.0], positive=False),
            ValueError,
            "c",
            "`c` must be nonnegative; got -3.0 at index 1.",
        ),
        (
            lambda: as_parameter_vector("c", []),
            ValueError,
            "c",
            "`c` must not be empty; got 0 elements.",
        ),
        (
            lambda: as_real_vector("w", [[1.0]]),
            ValueError,
            "w",
            "`w` must be a scalar or one-dimensional; got shape (1, 1).",
        ),
        (
            lambda: as_signal("y", [1.0], min_length=2),
            ValueError,
            "y",
            "`y` must have at least 2 samples; got 1 samples.",
        ),
        (
            lambda: as_signal("y", np.ones(10) * np.nan),
            ValueError,
            "y",
            "`y` must be finite; got nan at index 0.",
        ),
        (
            lambda: as_state_vector("x", [1.0], 2),
            ValueError,
            "x",
            "`x` must have shape (2,); got shape (1,).",
        ),
        (
            lambda: as_real_scalar("a", [1.0]),
            TypeError,
            "a",
            "`a` must be a real number; got [1.0].",
        ),
        (
            lambda: as_real_scalar("a", np.ones(2)),
            ValueError,
            "a",
            "`a` must be a scalar; got shape (2,).",
        ),
        (lambda: as_positive_scalar("m", -1), ValueError, "m", "`m` must be positive; got -1.0."),
        (
            lambda: as_nonnegative_scalar("m", -1),
            ValueError,
            "m",
            "`m` must be nonnegative; got -1.0.",
        ),
        (
            lambda: as_choice("method", "c", ("a", "b")),
            ValueError,
            "method",
            "`method` must be one of 'a', 'b'; got 'c'.",
        ),
        (lambda: as_count("n", 1.0), TypeError, "n", "`n` must be an integer; got 1.0."),
        (lambda: as_count("n", -2), ValueError, "n", "`n` must be nonnegative; got -2."),
    ]
    for call, exc, name, expected in cases:
        assert assert_rejects(call, exc, name) == expected
    with pytest.raises(ValueError, match=r"^`a` and `b` must have the same length"):
        check_same_length(a=[1.0], b=[1.0, 2.0])


def test_fmt_is_short_and_unambiguous():
    assert fmt(np.float64(0.1)) == "0.1"
    assert fmt(3) == "3"
    assert fmt("x") == "'x'"
    assert fmt(np.array([1.0, 2.0])) == "[1.0, 2.0]"
    assert fmt(np.zeros((3, 4))) == "an array of shape (3, 4)"
    assert len(fmt("x" * 500)) <= 60


def test_count_minimum_wording():
    assert as_count("n", 0) == 0
    assert as_count("n", 1, minimum=1) == 1
    with pytest.raises(ValueError, match=r"^`n` must be a positive integer; got 0\.$"):
        as_count("n", 0, minimum=1)
    with pytest.raises(ValueError, match=r"^`n` must be at least 3; got 2\.$"):
        as_count("n", 2, minimum=3)
    with pytest.raises(TypeError, match=r"^`n` must be an integer; got True\.$"):
        as_count("n", True, minimum=1)


# ----------------------------------------------------------------- shared mechanisms of issue 16
def test_ragged_arrays_are_named_by_every_helper():
    from presliding._validation import as_real_array

    for helper in (as_signal_, as_real_array):
        assert_rejects(lambda h=helper: h("displacement", [[1.0], [1.0, 2.0]]), ValueError,
                       "displacement")  # fmt: skip


def as_signal_(name, value):
    from presliding._validation import as_signal

    return as_signal(name, value)


def test_a_signal_whose_range_overflows_is_refused_naming_it():
    message = assert_rejects(lambda: as_signal_("time", [0.0, 1e308, -1e308]), ValueError, "time")
    assert "range max − min" in message


def test_renamed_makes_inner_errors_name_the_callers_argument():
    from presliding._validation import as_real_scalar, renamed

    nan = float("nan")
    with (
        pytest.raises(ValueError, match=r"^`applied_force` must be finite; got nan\.$"),
        renamed(force="applied_force"),
    ):
        as_real_scalar("force", nan)
    with pytest.raises(TypeError, match=r"^`other` must be a real"), renamed(force="x"):
        as_real_scalar("other", "x")  # an error naming another argument is left as it is


def test_lists_bounds_and_time_spans():
    from presliding._validation import as_bounds, as_list, check_time_span

    assert as_list("models", (1, 2)) == [1, 2]
    for bad in (None, 3.0, "ab", {"a": 1}):
        assert_rejects(lambda b=bad: as_list("models", b), TypeError, "models")
    assert as_bounds("bounds", {"a": (0, np.inf)}, ("a", "b")) == {"a": (0.0, np.inf)}
    assert_rejects(lambda: as_bounds("bounds", {"c": (0, 1)}, ("a",)), ValueError, "bounds")
    assert_rejects(lambda: as_bounds("bounds", {"a": (1, 0)}, ("a",)), ValueError, "bounds")
    assert_rejects(lambda: as_bounds("bounds", {"a": 1.0}, ("a",)), ValueError, "bounds")
    assert_rejects(lambda: as_bounds("bounds", 3.0, ("a",)), TypeError, "bounds")
    check_time_span("t_end", 1e12, 1e12)
    assert_rejects(lambda: check_time_span("t_end", 1e308, 1e308), ValueError, "t_end")


def test_resample_checks_the_size_before_allocating():
    from presliding import Measurement

    m = Measurement(np.array([0.0, 1.0, 2.0]), position=np.zeros(3))
    assert_rejects(lambda: m.resample(1e-12), ValueError, "step")
    assert_rejects(lambda: m.resample(1e-320), ValueError, "step")
    assert m.resample(0.5).time.shape == (5,)


def test_pint_quantities_are_converted_to_si_or_refused():
    """A Quantity in mm is a position in m everywhere a position enters; wrong kinds refused."""
    import warnings

    import pint

    import presliding as ps

    q = pint.UnitRegistry().Quantity
    y_mm = 3.0 * np.sin(np.linspace(0.0, 10.0, 300))
    model = ps.PIFriction(0.1, [500.0, 10.0], [1.0, 1.0])
    operator = ps.PIOperator([0.001, 0.002], [1.0, 1.0])
    batch = ps.PIBatch([[0.001, 0.002]], [[1.0, 1.0]])
    pid = ps.PID(400.0, 4e4, 0.0, dt=1e-3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # pint's UnitStrippedWarning would be an error
        for run in (model.force, operator.apply, batch.apply):
            np.testing.assert_array_equal(run(q(y_mm, "mm"))[0], run(y_mm * 1e-3)[0])
        a = ps.simulate(model, q(1000.0, "g"), q(0.2, "N"), initial_velocity=q(800.0, "mm/s"),
                        t_end=q(100.0, "ms"))  # fmt: skip
        b = ps.simulate(model, 1.0, 0.2, initial_velocity=0.8, t_end=0.1)
        np.testing.assert_array_equal(a.position, b.position)
        a = ps.simulate_loop(model, q(1.0, "kg"), pid, q(1.0, "mm"), t_end=q(0.1, "s"))
        b = ps.simulate_loop(model, 1.0, pid, 1e-3, t_end=0.1)
        np.testing.assert_array_equal(a.position, b.position)
    # a rotary axis: an angle in degrees is a position in rad
    np.testing.assert_allclose(model.force(q(y_mm, "deg"))[0], model.force(np.radians(y_mm))[0])
    with pytest.raises(ValueError, match=r"^`displacement` must be a position .* newton"):
        model.force(q(y_mm, "N"))
    with pytest.raises(ValueError, match=r"^`mass` must be a mass .* meter"):
        ps.simulate(model, q(1.0, "m"), t_end=1.0)
    with pytest.raises(ValueError, match=r"^`t_end` must be a time"):
        ps.simulate_loop(model, 1.0, pid, t_end=q(1.0, "m"))
    # an argument without a unit refuses a Quantity, never stripping it (a generic weight)
    with pytest.raises(TypeError, match=r"^`weight` must be a plain number or array \(it has no"):
        ps.PIOperator([0.001, 0.002], q([500.0, 10.0], "N/m"))
