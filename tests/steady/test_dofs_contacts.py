"""Every attractor lists its coordinates (``dofs``) and contact elements (``contacts``) in a form
that holds for n coordinates (docs/formats.md, "JSON contract"), checked against independent
references: the exact mean of the equation of motion over a period (the mean contact force is the
static load W = Q + F_pre), the attractor's own range fields, a numpy FFT of its time history at
f_e, and the contact force written out from the paper's Eq. 2.3 and integrated over samples."""

import json

import numpy as np
import pytest

from contactvib import ContactModel, attractor_history, find_attractors

DOF_KEYS = {"name", "unit", "min", "max", "app", "h1"}
CONTACT_KEYS = {"name", "loses_contact", "contact_loss_fraction", "mean_force_n"}
#: The mean contact force of a periodic orbit is W to this (relative): the identity is exact, the
#: quadrature of each step's interpolant too (polynomial force), the orbit closes to 1e-10.
MEAN_FORCE_RTOL = 1e-6


@pytest.fixture(scope="module")
def paper_point():
    model = ContactModel()
    exc = model.excitation(0.65, 360.0)
    return model, exc, find_attractors(exc, n_starts=256)


def test_mean_contact_force_of_every_periodic_attractor_is_q(paper_point):
    """⟨S c_n y^m2 + S h_n y^l ẏ⟩ over a period = Q (1 DOF, no preload): the period average of
    M ÿ = Q − F_c + P_a cos(2π f_e t), with ⟨ÿ⟩ = 0 and ⟨cos⟩ = 0."""
    model, _exc, result = paper_point
    periodic = [a for a in result if a.period is not None]
    assert len(periodic) >= 4 and {a.loses_contact for a in periodic} == {True, False}
    for a in periodic:
        assert a.mean_contact_force_n == pytest.approx(model.Q, rel=MEAN_FORCE_RTOL), a.period
        assert a.to_dict()["contacts"][0]["mean_force_n"] == a.mean_contact_force_n


def test_dofs_and_contacts_keys_and_values(paper_point):
    _model, _exc, result = paper_point
    d = json.loads(result.to_json())
    for a, obj in zip(result, d["attractors"]):
        assert [set(x) for x in obj["dofs"]] == [DOF_KEYS]
        assert [set(x) for x in obj["contacts"]] == [CONTACT_KEYS]
        dof, contact = obj["dofs"][0], obj["contacts"][0]
        assert (dof["name"], dof["unit"], contact["name"]) == ("y", "um", "contact")
        assert dof["app"] == obj["app_um"] and dof["min"] == obj["ymin_um"] and dof["max"] == obj["ymax_um"]
        assert contact["loses_contact"] is (obj["ymin_um"] < 0) is obj["loses_contact"]
        assert contact["contact_loss_fraction"] == obj["contact_loss_fraction"]
        # 2n Floquet multipliers for n = 1 coordinate, as [re, im] pairs
        n_mult = 2 * len(obj["dofs"]) if a.period is not None else 0
        assert len(obj["floquet_multipliers"]) == n_mult
        assert all(len(m) == 2 for m in obj["floquet_multipliers"])


def test_h1_is_the_fft_amplitude_at_fe(paper_point):
    """dofs[0].h1 against numpy's FFT of the attractor's time history over whole orbit periods:
    the bin at f_e of k periods is the k-th, its one-sided amplitude 2 |Y_k| / N."""
    model, exc, result = paper_point
    for a in result:
        k = a.period
        spp = 1024
        hist = attractor_history(exc, a, n_periods=k, samples_per_period=spp)
        y = hist.y_um[:-1]  # k whole periods, the endpoint left out
        amp = 2.0 * np.abs(np.fft.rfft(y)[k]) / y.size
        assert a.to_dict()["dofs"][0]["h1"] == pytest.approx(amp, rel=1e-6, abs=1e-9 * a.app_um), k


def test_mean_contact_force_against_eq_2_3_on_samples(paper_point):
    """The integrated mean force against Eq. 2.3 written out here (S c_n y^m2 + S h_n y^l ẏ for
    y > 0) and averaged over uniform samples of the time history (trapezoid rule, periodic)."""
    model, exc, result = paper_point
    for a in result:
        spp = 4000
        hist = attractor_history(exc, a, n_periods=a.period, samples_per_period=spp)
        y, ydot = hist.y_um[:-1] * 1e-6, hist.ydot_mm_s[:-1] * 1e-3
        f = np.where(y > 0, model.S * model.c_n * np.abs(y) ** model.m2
                     + model.S * model.h_n * np.abs(y) ** model.l * ydot, 0.0)
        assert a.mean_contact_force_n == pytest.approx(f.mean(), rel=1e-4)


def test_mean_contact_force_with_a_preload_is_w():
    """With a preload F_pre the static load is W = Q + F_pre, and so is the mean contact force of a
    periodic orbit (the force is evaluated by the compiled law of the model's family)."""
    model = ContactModel(preload=2.0 * ContactModel().Q)
    exc = model.excitation(0.5, 500.0)
    result = find_attractors(exc, n_starts=32)
    periodic = [a for a in result if a.period is not None]
    assert periodic
    for a in periodic:
        assert a.mean_contact_force_n == pytest.approx(model.W, rel=MEAN_FORCE_RTOL)
        assert a.mean_contact_force_n == pytest.approx(3.0 * model.Q, rel=MEAN_FORCE_RTOL)


def test_contact_force_is_the_spring_force_plus_damping():
    """ContactModel.contact_force: −spring_force at rest, plus S h_n y^l ẏ; 0 at y ≤ 0."""
    model = ContactModel()
    y = np.array([-1e-7, 0.0, 1e-7, model.y0, 3 * model.y0])
    v = np.array([0.1, 0.1, -0.02, 0.0, 0.05])
    ref = np.where(y > 0, model.S * model.c_n * np.abs(y) ** model.m2 + model.S * model.h_n * np.abs(y) ** model.l * v,
                   0.0)
    np.testing.assert_allclose(model.contact_force(y, v), ref, rtol=1e-12, atol=0)
    np.testing.assert_allclose(model.contact_force(y, 0.0), -model.spring_force(y), rtol=1e-14, atol=0)
    assert model.contact_force(model.y0, 0.0) == pytest.approx(model.Q, rel=1e-12)
