"""Jacobi and Gauss-Seidel converge to the single-FMU solution of the same loop as the step
shrinks, with the first order of a zero-order-hold coupling."""
from __future__ import annotations

import pytest

from cosim.compiler.build import build_model
from cosim.studies.convergence import BIKE, REFERENCE, convergence, format_rows, held_input_algorithms

ORDER_RANGE = (0.9, 1.1)  # observed order on the finest halving


@pytest.fixture(scope="module")
def rows(fmus, tmp_path_factory):
    # The single-FMU reference loop is an example, not an exported model: built here.
    reference = build_model(REFERENCE, tmp_path_factory.mktemp("convergence")).fmu
    result = convergence(fmus[BIKE], reference)
    print("\n" + format_rows(result))
    return result


@pytest.mark.parametrize("algorithm", held_input_algorithms())
def test_error_shrinks_with_order_one(rows, algorithm):
    mine = [r for r in rows if r.algorithm == algorithm]
    errors = [r.error for r in mine]
    assert all(a > b for a, b in zip(errors, errors[1:])), errors
    assert ORDER_RANGE[0] <= mine[-1].order <= ORDER_RANGE[1], mine[-1]
    assert errors[-1] < 5e-3  # rad, at h = 5 ms


def test_gauss_seidel_more_accurate_than_jacobi(rows):
    for h in {r.step for r in rows}:
        jacobi = next(r.error for r in rows if r.algorithm == "jacobi" and r.step == h)
        gauss_seidel = next(r.error for r in rows if r.algorithm == "gauss-seidel" and r.step == h)
        assert gauss_seidel < jacobi
