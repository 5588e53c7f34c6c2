"""The model from Python: values, residuals, RMSE and the Jacobian; arrays without copies."""

from __future__ import annotations

import numpy as np
import pytest

import brdf_sls as bs


@pytest.fixture(scope="module")
def data():
    return bs.DataSet.synthetic("tuning", samples=400, sigma=0.05, seed=2)


def test_arrays_round_trip_and_evaluate_equals_values(data):
    clean = bs.DataSet.synthetic("tuning", samples=400, sigma=0.0, seed=2)
    m = bs.Model()
    f = m.evaluate("tuning", clean.u, clean.v)
    # Noiseless synthetic values are the model's values (same formula, SIMD vs scalar).
    np.testing.assert_allclose(f, clean.values, rtol=1e-12, atol=1e-14)
    again = bs.DataSet.from_arrays(clean.u, clean.v, clean.values)
    assert m.rmse("tuning", again) == m.rmse("tuning", clean)


def test_rmse_is_the_root_mean_square_of_the_residuals(data):
    m = bs.Model()
    x = m.encode("tuning") + 0.01
    r = m.residuals(x, data)
    assert r.shape == (len(data),)
    assert m.rmse(x, data) == pytest.approx(np.sqrt(np.mean(r**2)), rel=1e-12)
    back, want = m.decode(m.encode("tuning")), bs.named_params("tuning")
    assert back["kd"] == pytest.approx(want["kd"], rel=1e-14)
    for a, b in zip(back["lobes"], want["lobes"]):
        assert a == pytest.approx(b, rel=1e-12, abs=1e-12)


def test_jacobian_matches_central_differences(data):
    m = bs.Model(lobes=1, kind="anisotropic")
    x = m.encode("tuning") * 0.97 + 0.01
    x = np.clip(x, m.lower, m.upper)
    jac = m.jacobian(x, data)
    assert jac.shape == (len(data), m.dim)
    assert jac.flags.f_contiguous  # the evaluator's column-major buffer, not copied
    for j in range(m.dim):
        h = 1e-6 * max(1.0, abs(x[j]))
        xp, xm = x.copy(), x.copy()
        xp[j] += h
        xm[j] -= h
        fd = (m.residuals(xp, data) - m.residuals(xm, data)) / (2 * h)
        np.testing.assert_allclose(jac[:, j], fd, rtol=1e-5, atol=1e-6 * np.abs(fd).max())


def test_columns_are_read_only_views_without_copies(data):
    a = data.values
    b = data.column("value")
    assert np.shares_memory(a, b)  # two views of the one stored column
    assert not a.flags.writeable
    with pytest.raises(ValueError):
        a[0] = 1.0
    assert data.column("uz").min() >= 0.0


def test_fixed_and_isotropic_layouts(data):
    m = bs.Model(lobes=2, kind="isotropic", fixed={"lobe2.n": 5.0})
    assert m.names == ["kd", "lobe1.cxy", "lobe1.cz", "lobe1.n", "lobe2.cxy", "lobe2.cz"]
    p = m.decode(np.clip(np.zeros(m.dim), m.lower, m.upper))
    assert p["lobes"][1]["n"] == 5.0
