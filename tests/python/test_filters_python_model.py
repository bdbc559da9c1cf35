"""bcassim's filters on a model written in Python: a linear-Gaussian model gives the exact Kalman
posterior through UKF (every sigma-point set), ROUKF (full and reduced rank) and ETKF (against the
Kalman update of its own forecast ensemble); threads, observation operators and errors."""
import numpy as np
import pytest

import bcassim
from bcassim.assimilation import (EtkfFilter, ForecastModel, Observation, ObservationOperator,
                                  Parameter, RoukfFilter, StochasticState, UkfFilter)

A = np.array([[0.9, 0.2], [-0.1, 0.95]])
B = np.array([0.05, 0.1])  # x' = A x + B theta: the parameter theta drives the state
R = np.diag([0.02**2, 0.05**2])


class LinearModel(ForecastModel):
    """x_{k+1} = A x_k + B theta; the observable is the new state itself."""

    def __init__(self):
        super().__init__()
        self.calls = 0

    def state_size(self):
        return 2

    def observable_size(self):
        return 2

    def forecast(self, state, params):
        self.calls += 1
        new = A @ state + B * params[0]
        return new, new


def kalman_step(m, P, y):
    F = np.block([[A, B[:, None]], [np.zeros((1, 2)), np.ones((1, 1))]])
    H = np.hstack([np.eye(2), np.zeros((2, 1))])
    mf, Pf = F @ m, F @ P @ F.T
    S = H @ Pf @ H.T + R
    K = Pf @ H.T @ np.linalg.inv(S)
    return mf + K @ (y - H @ mf), (np.eye(3) - K @ H) @ Pf


def observations(steps):
    rng = np.random.default_rng(7)
    x, theta, ys = np.array([1.0, -0.5]), 2.0, []
    for _ in range(steps):
        x = A @ x + B * theta
        ys.append(x + rng.multivariate_normal(np.zeros(2), R))
    return ys


def layout(physical_sd):
    return StochasticState([0.8, -0.3], physical_sd, [Parameter("theta", 1.0, 0.7)])


@pytest.mark.parametrize("make", [
    lambda s: UkfFilter(layout([0.1, 0.2]), LinearModel(), sigma_points="star"),
    lambda s: UkfFilter(layout([0.1, 0.2]), LinearModel(), sigma_points="canonical"),
    lambda s: UkfFilter(layout([0.1, 0.2]), LinearModel(), sigma_points="simplex"),
    lambda s: RoukfFilter(layout([0.1, 0.2]), LinearModel()),
], ids=["ukf-star", "ukf-canonical", "ukf-simplex", "roukf-full-rank"])
def test_linear_gaussian_model_gives_the_exact_kalman_posterior(make):
    f = make(None)
    m = np.array([0.8, -0.3, 1.0])
    P = np.diag([0.1, 0.2, 0.7]) ** 2
    F = np.block([[A, B[:, None]], [np.zeros((1, 2)), np.ones((1, 1))]])
    for y in observations(6):
        # what an adaptive R needs (issue 15): ||y - H x_f||^2 and tr(H P_f H^T), H = [I 0]
        innovation, spread = y - (F @ m)[:2], np.trace((F @ P @ F.T)[:2, :2])
        m, P = kalman_step(m, P, y)
        report = f.step(Observation(y, variance=np.diag(R)))
        np.testing.assert_allclose(f.mean, m, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(f.covariance(), P, rtol=1e-9, atol=1e-14)
        assert report.observed == 2
        assert report.innovation_squared_norm == pytest.approx(innovation @ innovation, rel=1e-9)
        assert report.predicted_observation_trace == pytest.approx(spread, rel=1e-9)
    mean, sd = f.estimate()
    np.testing.assert_allclose(mean, m, rtol=1e-10)
    np.testing.assert_allclose(sd, np.sqrt(np.diag(P)), rtol=1e-9)


def test_roukf_at_reduced_rank_is_the_kalman_filter_with_a_known_initial_state():
    f = RoukfFilter(layout([0.0, 0.0]), LinearModel())
    m = np.array([0.8, -0.3, 1.0])
    P = np.diag([0.0, 0.0, 0.7]) ** 2
    for y in observations(6):
        m, P = kalman_step(m, P, y)
        f.step(Observation(y, variance=np.diag(R)))
        np.testing.assert_allclose(f.mean, m, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(f.covariance(), P, rtol=1e-9, atol=1e-14)


def test_etkf_analysis_is_the_kalman_update_of_its_forecast_ensemble():
    f = EtkfFilter(layout([0.1, 0.2]), LinearModel(), members=8, seed=3)
    F = np.block([[A, B[:, None]], [np.zeros((1, 2)), np.ones((1, 1))]])
    H = np.hstack([np.eye(2), np.zeros((2, 1))])
    for y in observations(4):
        forecast = F @ np.asarray(f.members)
        mf = forecast.mean(axis=1)
        Xf = forecast - mf[:, None]
        Pf = Xf @ Xf.T / (forecast.shape[1] - 1)
        K = Pf @ H.T @ np.linalg.inv(H @ Pf @ H.T + R)
        f.step(Observation(y, variance=np.diag(R)))
        np.testing.assert_allclose(f.mean, mf + K @ (y - H @ mf), rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(f.covariance(), (np.eye(3) - K @ H) @ Pf, rtol=1e-9,
                                   atol=1e-14)


def test_threads_give_the_same_estimate_as_one_thread():
    runs = []
    for threads in (1, 2):
        models = [LinearModel() for _ in range(threads)]
        f = UkfFilter(layout([0.1, 0.2]), models, threads=threads)
        for y in observations(5):
            f.step(Observation(y, sigma=0.03))
        runs.append(f.mean)
        assert sum(m.calls for m in models) == 5 * 7  # 2n + 1 star sigma points per step
    np.testing.assert_array_equal(runs[0], runs[1])


class FirstComponent(ObservationOperator):
    """Observes the first entry of the observable only."""

    def linearize(self, mean_observable, frame):
        return frame

    def predict(self, observable):
        return observable[:1]


def test_a_python_observation_operator_is_used():
    f = UkfFilter(layout([0.1, 0.2]), LinearModel(), observation=FirstComponent())
    m = np.array([0.8, -0.3, 1.0])
    P = np.diag([0.1, 0.2, 0.7]) ** 2
    F = np.block([[A, B[:, None]], [np.zeros((1, 2)), np.ones((1, 1))]])
    H = np.array([[1.0, 0.0, 0.0]])
    for y in observations(3):
        mf, Pf = F @ m, F @ P @ F.T
        K = Pf @ H.T / (H @ Pf @ H.T + R[0, 0])
        m, P = mf + (K * (y[0] - H @ mf)).ravel(), (np.eye(3) - K @ H) @ Pf
        f.step(Observation(y[:1], variance=[R[0, 0]]))
        np.testing.assert_allclose(f.mean, m, rtol=1e-10)


class Squares(ObservationOperator):
    """y = (o0^2, o1^2), linearised at the mean it is given: predict is the tangent there."""

    def linearize(self, mean_observable, frame):
        self.at = np.array(mean_observable[:2])
        return frame

    def predict(self, observable):
        return self.at**2 + 2 * self.at * (observable[:2] - self.at)


def test_relinearizations_reach_the_maximum_a_posteriori_of_one_frame():
    # One frame of a nonlinear operator: each pass linearises it again at the analysed mean, and
    # the passes' fixed point is the MAP of the prior and the frame (Gauss-Newton, here in numpy).
    mu, sd, r = np.array([0.8, -0.3, 1.0]), np.array([0.1, 0.2, 0.7]), 0.01
    F = np.block([[A, B[:, None]], [np.zeros((1, 2)), np.ones((1, 1))]])
    mf, Pf = F @ mu, F @ np.diag(sd**2) @ F.T
    y = np.array([1.2, 0.5]) ** 2
    x = mf.copy()
    for _ in range(50):  # Gauss-Newton on the MAP cost
        J = np.zeros((2, 3))
        J[0, 0], J[1, 1] = 2 * x[0], 2 * x[1]
        g = np.linalg.solve(Pf, x - mf) - J.T @ (y - x[:2] ** 2) / r**2
        x -= np.linalg.solve(np.linalg.inv(Pf) + J.T @ J / r**2, g)
    for passes in (0, 30):
        f = UkfFilter(StochasticState(mu[:2], sd[:2], [Parameter("theta", mu[2], sd[2])]),
                      LinearModel(), observation=Squares(), relinearizations=passes)
        report = f.step(Observation(y, sigma=r))
        if passes == 0:
            assert report.relinearizations == 0
            assert np.abs(f.mean - x).max() > 1e-2
        else:
            assert 1 <= report.relinearizations < passes
            np.testing.assert_allclose(f.mean, x, atol=1e-3)


def test_prediction_only_steps_and_errors():
    f = RoukfFilter(layout([0.1, 0.2]), LinearModel())
    assert f.step().observed == 0  # no observation: the step predicts only

    class WrongSize(LinearModel):
        def forecast(self, state, params):
            return np.zeros(3), np.zeros(2)

    with pytest.raises(ValueError, match="new_state has 3 entries, expected 2"):
        RoukfFilter(layout([0.1, 0.2]), WrongSize()).step()

    class Failing(LinearModel):
        def forecast(self, state, params):
            raise RuntimeError("the simulator diverged")

    with pytest.raises(RuntimeError, match="the simulator diverged"):
        UkfFilter(layout([0.1, 0.2]), [Failing(), Failing()], threads=2).step()
    with pytest.raises(ValueError, match="1 for 2 threads"):
        UkfFilter(layout([0.1, 0.2]), LinearModel(), threads=2)
    with pytest.raises(bcassim.InputError, match="observation frame has 3 values"):
        f.step(Observation([1.0, 2.0, 3.0], sigma=0.1))
    with pytest.raises(bcassim.InputError):
        StochasticState([0.0], [0.1], [Parameter("k", 1.0, -1.0)])  # sigma <= 0


class LinearisedAtItsReference(ForecastModel):
    """A static model written in Python: y = (a^2, a b, b^2), each forecast linearised about the
    model's reference, which recentre() moves (as a static frame's chord steps are linearised
    about the analysed mean's equilibrium)."""

    def __init__(self, reference, can_recentre=True):
        super().__init__()
        self.reference = np.array(reference, dtype=float)
        self.can_recentre = can_recentre
        self.recentres = 0

    @staticmethod
    def h(o):
        return np.array([o[0] ** 2, o[0] * o[1], o[1] ** 2])

    @staticmethod
    def jacobian(o):
        return np.array([[2 * o[0], 0.0], [o[1], o[0]], [0.0, 2 * o[1]]])

    def state_size(self):
        return 0

    def observable_size(self):
        return 3

    def forecast(self, state, params):
        r = self.reference
        return np.zeros(0), self.h(r) + self.jacobian(r) @ (params - r)

    def recentre(self, state, params):
        if not self.can_recentre:
            return False
        self.reference = np.array(params, dtype=float)
        self.recentres += 1
        return True


def test_roukf_reforecasts_reach_the_maximum_a_posteriori_of_a_python_model():
    mu, sd, sigma = np.array([1.0, -0.5]), np.array([0.4, 0.3]), 0.05
    y = LinearisedAtItsReference.h(np.array([1.5, -0.2]))
    # The MAP by Gauss-Newton, apart from the filter.
    Pinv = np.diag(1 / sd**2)
    theta = mu.copy()
    for _ in range(100):
        J = LinearisedAtItsReference.jacobian(theta)
        g = Pinv @ (theta - mu) - J.T @ (y - LinearisedAtItsReference.h(theta)) / sigma**2
        theta -= np.linalg.solve(Pinv + J.T @ J / sigma**2, g)
    layout = StochasticState([], [], [Parameter("a", mu[0], sd[0]), Parameter("b", mu[1], sd[1])])
    results = {}
    for name, model, reforecasts in [("once", LinearisedAtItsReference(mu), 0),
                                     ("iterated", LinearisedAtItsReference(mu), 40),
                                     ("refused", LinearisedAtItsReference(mu, False), 40)]:
        f = RoukfFilter(layout, model, reforecasts=reforecasts)
        report = f.step(Observation(y, sigma=sigma))
        results[name] = (f.estimate()[0], report.reforecasts, model.recentres)
    once, iterated, refused = results["once"], results["iterated"], results["refused"]
    assert np.abs(iterated[0] - theta).max() < 1e-4
    assert np.abs(once[0] - theta).max() > 1e-2
    assert 1 <= iterated[1] <= 40 and iterated[2] == iterated[1]
    assert refused[1] == 0 and np.array_equal(refused[0], once[0])
    with pytest.raises(ValueError, match="reforecasts must be >= 0"):
        RoukfFilter(layout, LinearisedAtItsReference(mu), reforecasts=-1)
