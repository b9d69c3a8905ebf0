"""NetworkStructure: validation on construction and the helpers."""

from __future__ import annotations

import numpy as np
import pytest

from presliding import PIFriction
from presliding.hysteresis.densities import Uniform
from presliding.network import (
    NetworkStructure,
    chain_structure,
    modal_structure,
    multi_contact_structure,
)

COULOMB = PIFriction(1.0)


def test_a_structure_holds_its_arrays_read_only():
    s = NetworkStructure([2.0, 3.0], [[2.0, -1.0], [-1.0, 1.0]], [[1.0], [0.0]], [COULOMB],
                         forcing=[0.0, 1.0])  # fmt: skip
    assert s.mass.shape == (2, 2) and s.mass[1, 1] == 3.0
    assert s.n_coordinates == 2 and s.n_contacts == 1
    assert not s.mass.flags.writeable and not s.contacts.flags.writeable
    np.testing.assert_array_equal(s.force_at(5.0), [0.0, 1.0])
    assert not s.is_damped
    assert s.breakaway_level[0] == 1.0


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"mass": [[1.0, 0.0], [0.0, -1.0]]}, "mass` must be positive definite"),
        ({"mass": [[1.0, 0.5], [0.0, 1.0]]}, "mass` must be symmetric"),
        ({"stiffness": [[-1.0, 0.0], [0.0, 1.0]]}, "stiffness` must be positive semidefinite"),
        ({"stiffness": np.eye(3)}, r"stiffness` must be a square matrix of shape \(2, 2\)"),
        ({"contacts": [[1.0, 0.0], [0.0, 0.0]]}, "zero column; column 1"),
        ({"contacts": [[1.0], [0.0], [0.0]]}, r"contacts` must have shape \(2, n_c\)"),
        ({"friction": [COULOMB, COULOMB]}, r"one model per contact \(1\); got 2"),
        ({"friction": [PIFriction(0.0, [1.0], [1.0])]}, "Coulomb element c1 > 0"),
        ({"friction": [PIFriction(0.0, density=Uniform(1.0, 1.0))]}, "finite elements"),
        ({"forcing": [1.0, 2.0, 3.0]}, r"forcing` must be a constant of shape \(2,\)"),
        ({"forcing": ([0.0, 1.0], [[1.0, 2.0]])}, r"values must have shape \(2, 2\)"),
        ({"forcing": ([1.0, 0.0], [[1.0, 2.0], [0.0, 0.0]])}, "strictly increasing"),
        ({"damping": [[0.0, 1.0], [1.0, 0.0]]}, "damping` must be positive semidefinite"),
    ],
)
def test_bad_input_is_an_error_naming_the_argument(kwargs, match):
    args = {"mass": np.eye(2), "stiffness": np.eye(2), "contacts": [[1.0], [0.0]],
            "friction": [COULOMB]}  # fmt: skip
    extra = {k: kwargs.pop(k) for k in ("forcing", "damping") if k in kwargs}
    args.update(kwargs)
    with pytest.raises((ValueError, TypeError), match=match):
        NetworkStructure(**args, **extra)


def test_a_friction_entry_of_another_type_is_a_type_error():
    with pytest.raises(TypeError, match=r"friction\[0\]"):
        NetworkStructure(1.0, 1.0, [[1.0]], ["coulomb"])


def test_chain_has_springs_between_neighbours_and_one_contact_per_mass():
    s = chain_structure(3, [1.0, 2.0, 3.0], [10.0, 20.0, 30.0], COULOMB, damping=0.5)
    np.testing.assert_array_equal(s.stiffness, [[30.0, -20.0, 0.0], [-20.0, 50.0, -30.0],
                                                [0.0, -30.0, 30.0]])  # fmt: skip
    np.testing.assert_array_equal(s.contacts, np.eye(3))
    np.testing.assert_array_equal(s.damping[0], [1.0, -0.5, 0.0])
    assert len(s.friction) == 3 and s.is_damped


def test_mass_on_several_contacts_and_modal_model():
    s = multi_contact_structure(2.0, 5.0, [COULOMB, PIFriction(0.5, [10.0], [0.1])])
    np.testing.assert_array_equal(s.contacts, [[1.0, 1.0]])
    m = modal_structure([1.0, 3.0], [[1.0, 0.5], [0.2, -1.0]], COULOMB, damping_ratios=0.01)
    np.testing.assert_array_equal(m.stiffness, np.diag([1.0, 9.0]))
    np.testing.assert_allclose(np.diag(m.damping), [0.02, 0.06])
    assert m.n_contacts == 2
    with pytest.raises(ValueError, match="n_masses"):
        chain_structure(0, 1.0, 1.0, COULOMB)


def test_per_contact_sums_with_contacts_without_elements():
    from presliding.network._contacts import Contacts

    models = [PIFriction(1.0), PIFriction(1.0, [1.0, 2.0, 3.0], [1.0, 1.0, 1.0]), PIFriction(1.0),
              PIFriction(1.0, [4.0], [1.0]), PIFriction(1.0)]  # fmt: skip
    cts = Contacts.of(models)
    values = np.array([1.0, 2.0, 4.0, 8.0])
    np.testing.assert_array_equal(cts.per_contact(values), [0.0, 7.0, 0.0, 8.0, 0.0])
    np.testing.assert_array_equal(cts.per_contact(np.vstack([values, -values]))[1],
                                  [0.0, -7.0, 0.0, -8.0, 0.0])  # fmt: skip
    trailing = Contacts.of(models[1:3])
    np.testing.assert_array_equal(trailing.per_contact(values[:3]), [7.0, 0.0])


@pytest.mark.parametrize(
    ("build", "error", "match"),
    [
        (lambda: chain_structure(2, 1.0, -1.0, COULOMB), ValueError,
         r"`spring` must be nonnegative; got -1\.0 at index 0"),
        (lambda: chain_structure(3, [1.0, 2.0], 1.0, COULOMB), ValueError,
         r"`mass` must be a number or one value per mass \(3\); got shape \(2,\)"),
        (lambda: chain_structure(3, 1.0, 1.0, COULOMB, damping=[1.0, -1.0, 0.0]), ValueError,
         "`damping` must be nonnegative"),
        (lambda: chain_structure(2, [1.0, 0.0], 1.0, COULOMB), ValueError,
         "`mass` must be positive"),
        (lambda: chain_structure(2, 1.0, 1.0, COULOMB, sparse="yes"), TypeError, "`sparse`"),
        (lambda: modal_structure([1.0, 2.0], [1.0, 2.0, 3.0], COULOMB), ValueError,
         r"`mode_shapes` must have shape \(2, n_c\)"),
        (lambda: modal_structure([1.0, 2.0], [[1.0, 0.0], [0.0, 0.0]], COULOMB), ValueError,
         "`mode_shapes` must not have a zero column"),
        (lambda: modal_structure([1.0, 2.0], [[1.0], [0.0]], COULOMB, damping_ratios=[0.1] * 3),
         ValueError, r"`damping_ratios` must be a number or one per mode \(2\)"),
        (lambda: modal_structure([[1.0, 2.0]], [[1.0], [0.0]], COULOMB), ValueError,
         "`frequencies` must be one or more numbers"),
        (lambda: multi_contact_structure(1.0, 1.0, []), ValueError,
         "`friction` must hold at least one model"),
        (lambda: multi_contact_structure([1.0, 2.0], 1.0, [COULOMB]), ValueError,
         "`mass` must be one number"),
    ],
)  # fmt: skip
def test_the_helpers_name_their_own_arguments(build, error, match):
    """Not `stiffness` for `spring`, not `contacts` for `mode_shapes` or `friction`, and no
    numpy broadcast or reshape message."""
    with pytest.raises(error, match=match):
        build()


def test_a_dense_chain_too_large_is_refused_before_allocating():
    """30,000 masses ask for 7·n² = 6.3e9 numbers (50 GB) of dense matrices: refused with
    the size and the memory, pointing to sparse=True, in no time (nothing allocated)."""
    import time

    start = time.process_time()
    with pytest.raises(ValueError, match=r"`n_masses` must ask for at most .*got 30000.*"
                                         r"GiB.*sparse=True"):  # fmt: skip
        chain_structure(30000, 1.0, 1.0, COULOMB)
    with pytest.raises(ValueError, match="got 200000"):
        chain_structure(200000, 1.0, 1.0, COULOMB)
    assert time.process_time() - start < 0.5


def test_a_sparse_chain_holds_the_same_structure_and_runs_exactly():
    import scipy.sparse

    model = PIFriction(0.5, [300.0], [0.2])
    dense = chain_structure(4, [1.0, 2.0, 1.5, 1.0], 100.0, model, damping=0.5)
    sparse = chain_structure(4, [1.0, 2.0, 1.5, 1.0], 100.0, model, damping=0.5, sparse=True)
    assert sparse.is_sparse and not dense.is_sparse
    for name in ("mass", "stiffness", "damping", "contacts"):
        assert scipy.sparse.issparse(getattr(sparse, name))
        np.testing.assert_array_equal(getattr(sparse, name).toarray(), getattr(dense, name))
    big = chain_structure(200_000, 1.0, 1.0, COULOMB, sparse=True)
    assert big.n_coordinates == 200_000 and big.stiffness.nnz == 3 * 200_000 - 2
    from presliding.network import simulate_network

    a = simulate_network(dense, 1.0, None, [0.3, 0.0, -0.2, 0.1])
    b = simulate_network(sparse, 1.0, None, [0.3, 0.0, -0.2, 0.1])
    np.testing.assert_array_equal(a.position, b.position)
    with pytest.raises(ValueError, match="exact path holds dense matrices"):
        simulate_network(big, 1.0)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"mass": "sparse_indefinite"}, "mass` must be positive definite; its LDLᵀ"),
        ({"stiffness": "sparse_asymmetric"}, "stiffness` must be symmetric"),
        ({"contacts": "sparse_zero_column"}, "zero column; column 1"),
    ],
)
def test_sparse_matrices_are_checked_like_dense_ones(kwargs, match):
    import scipy.sparse

    bad = {"sparse_indefinite": scipy.sparse.diags_array([1.0, -1.0]),
           "sparse_asymmetric": scipy.sparse.csr_array([[1.0, 0.5], [0.0, 1.0]]),
           "sparse_zero_column": scipy.sparse.csr_array([[1.0, 0.0], [0.0, 0.0]])}  # fmt: skip
    args = {"mass": scipy.sparse.identity(2), "stiffness": scipy.sparse.identity(2),
            "contacts": scipy.sparse.identity(2)}  # fmt: skip
    args.update({k: bad[v] for k, v in kwargs.items()})
    with pytest.raises(ValueError, match=match):
        NetworkStructure(args["mass"], args["stiffness"], args["contacts"], [COULOMB] * 2)


def test_repr_is_short_and_a_notebook_shows_a_table():
    """A 300-mass chain's repr was 19 kB (every matrix printed)."""
    s = chain_structure(300, 1.0, 10.0, PIFriction(0.5, [100.0, 50.0], [0.1, 0.1]))
    text = repr(s)
    assert len(text) < 200
    assert text.startswith("NetworkStructure(n=300, n_contacts=300, n_elements=600")
    page = s._repr_html_()
    assert "<table>" in page and "coordinates" in page and "300" in page and "N/m" not in text
