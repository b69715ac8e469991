"""The exact MI of every task in ``benchmarks/bench_mi_accuracy.py``, checked independently.

The accuracy table's truth column must not rest on the formulas that produce it.
References, each a different route to the same number:

- Gaussian MI ``0.5 ln(det S_xx det S_yy / det S)``: the canonical-correlation form
  ``-0.5 sum ln(1 - c_i^2)`` (c_i the singular values of S_xx^-1/2 S_xy S_yy^-1/2;
  Cover & Thomas 2006, ch. 8; Kullback 1959); the "2-pair" and "dense" covariances
  rebuilt from the latent-variable model of Beyond Normal (Czyz et al. 2023,
  ``GaussianLVMParametrization``) by drawing the latents.
- Student-t MI (Arellano-Valle et al. 2013, closed form with digamma): entropies by 1-D
  radial quadrature of scipy's ``multivariate_t.logpdf`` (h(k) = -E ln p).
- Additive uniform noise: h(X + N) - h(N) by quadrature of the convolution density.
- The "X" mixture: Monte Carlo of ``ln p(x, y) - ln p(x) - ln p(y)`` with scipy densities.
- The outlier mixture (1 % of rows far and independent): Monte Carlo of
  ``ln p(x, y) - ln p(x) - ln p(y)`` over iid draws of the mixture, scipy densities.
- Rounded normal pair: cell probabilities from scipy's bivariate normal CDF
  (inclusion-exclusion), and the limit step -> 0 (the continuous MI).
- Conditional MI of the Gaussian CMI tasks: the partial correlation from the Schur
  complement, the analytic 0.5 ln(1 + b^2), and the covariance of the generative model
  (x = w.z + e_x, y = b x + w.z + e_y) drawn directly.
- Transformed tasks: MI is invariant under strictly increasing maps of each variable
  (Cover & Thomas 2006, sec. 8.6), so the check is that each map is strictly increasing
  and that the bimodal task's marginals are the published mixtures (Kolmogorov-Smirnov).
"""

import importlib.util
import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy import integrate, special, stats

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_mi_accuracy.py"


@pytest.fixture(scope="module")
def bench():
    spec = importlib.util.spec_from_file_location("bench_mi_accuracy", BENCH)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def tasks(bench):
    return bench.build_tasks()


def canonical_mi(cov, dx):
    sxx, syy, sxy = cov[:dx, :dx], cov[dx:, dx:], cov[:dx, dx:]

    def inv_sqrt(m):
        w, v = np.linalg.eigh(m)
        return v @ np.diag(w**-0.5) @ v.T

    c = np.linalg.svd(inv_sqrt(sxx) @ sxy @ inv_sqrt(syy), compute_uv=False)
    return -0.5 * np.sum(np.log1p(-(c**2)))


def student_entropy_quadrature(k, df):
    """-E ln p of a standard k-variate t, integrating scipy's logpdf along the radius."""
    dist = stats.multivariate_t(loc=np.zeros(k), shape=np.eye(k), df=df)
    surface = 2 * math.pi ** (k / 2) / special.gamma(k / 2)

    def integrand(u):  # r = tan(u) maps [0, pi/2) onto [0, inf)
        r = math.tan(u)
        point = np.zeros(k)
        point[0] = r
        lp = dist.logpdf(point)
        return -surface * r ** (k - 1) * math.exp(lp) * lp / math.cos(u) ** 2

    value, err = integrate.quad(integrand, 0.0, math.pi / 2, limit=400, epsabs=1e-11)
    assert err < 1e-7
    return value


def test_gaussian_truths_equal_the_canonical_correlation_form(bench, tasks):
    for name, cov, dx in [
        ("normal-1x1", bench.corr2(0.75), 1),
        ("dense-2x2", bench.dense_cov(2, 2), 2),
        ("dense-3x3", bench.dense_cov(3, 3), 3),
        ("sparse-2x2", bench.sparse_cov(2, 2), 2),
        ("sparse-3x3", bench.sparse_cov(3, 3), 3),
    ]:
        assert tasks[name].truth == pytest.approx(canonical_mi(cov, dx), rel=1e-12), name
    assert tasks["normal-1x1"].truth == pytest.approx(-0.5 * math.log(1 - 0.75**2), rel=1e-12)
    # two independent pairs correlated 0.8 (the paper's "2-pair", strength 2)
    assert tasks["sparse-2x2"].truth == pytest.approx(-math.log(1 - 0.8**2), rel=1e-12)


def test_sparse_and_dense_covariances_follow_the_latent_variable_model(bench):
    # Beyond Normal's 2-pair model: X_i = 2 Z_i + E_i (i < 2), 2 V_i + E_i otherwise;
    # Y_i alike with the same Z_i and its own noise; all latents iid N(0, 1)
    rng = np.random.default_rng(11)
    n, dx = 400_000, 3
    z = rng.standard_normal((n, 2))
    x = rng.standard_normal((n, dx))
    y = rng.standard_normal((n, dx))
    x[:, :2] += 2 * z
    y[:, :2] += 2 * z
    x[:, 2:] += 2 * rng.standard_normal((n, dx - 2))
    y[:, 2:] += 2 * rng.standard_normal((n, dx - 2))
    emp = np.corrcoef(np.hstack([x, y]).T)
    # sd of a sample correlation <= 1 / sqrt(n) = 0.0016
    assert np.max(np.abs(emp - bench.sparse_cov(3, 3))) < 0.01
    # dense: X_i = U + E_i, Y_j = U + F_j, correlation 1 / 2 everywhere
    u = rng.standard_normal((n, 1))
    dense = np.hstack([u + rng.standard_normal((n, 2)), u + rng.standard_normal((n, 2))])
    assert np.max(np.abs(np.corrcoef(dense.T) - bench.dense_cov(2, 2))) < 0.01


@pytest.mark.parametrize("dx, dy, df", [(1, 1, 1), (1, 1, 2), (1, 1, 3), (1, 1, 5),
                                        (2, 2, 1), (2, 2, 2), (3, 3, 2)])
def test_student_mi_equals_radial_quadrature_of_the_entropies(bench, dx, dy, df):
    h = {k: student_entropy_quadrature(k, df) for k in {dx, dy, dx + dy}}
    assert bench.student_mi(dx, dy, df) == pytest.approx(h[dx] + h[dy] - h[dx + dy], abs=1e-7)


def test_student_1x1_df1_is_the_bivariate_cauchy_value(bench):
    # h(Cauchy) = ln(4 pi); the standard bivariate t with df 1 has h = ln(2 pi) + 3 (from
    # its radial law: -E ln p = ln(2 pi) + 1.5 E ln(1 + r^2) with E ln(1 + r^2) = 2)
    assert bench.student_mi(1, 1, 1) == pytest.approx(
        2 * math.log(4 * math.pi) - (math.log(2 * math.pi) + 3.0), abs=1e-12)


@pytest.mark.parametrize("eps", [0.1, 0.75])
def test_additive_uniform_mi_by_quadrature_of_the_convolution(bench, eps):
    def density(v):  # Y = X + N: (length of [v - eps, v + eps] within [0, 1]) / (2 eps)
        return max(0.0, min(v + eps, 1.0) - max(v - eps, 0.0)) / (2 * eps)

    def neg_plogp(v):
        p = density(v)
        return -p * math.log(p) if p > 0 else 0.0

    breaks = sorted({-eps, eps, 1 - eps, 1 + eps})
    h_y = sum(integrate.quad(neg_plogp, a, b, epsabs=1e-13)[0]
              for a, b in zip(breaks[:-1], breaks[1:], strict=True))
    assert bench.additive_uniform_mi(eps) == pytest.approx(h_y - math.log(2 * eps), abs=1e-9)


def test_mixture_x_mi_agrees_with_monte_carlo(bench, tasks):
    rng = np.random.default_rng(5)
    x, y, _ = tasks["X-mixture-1x1"].sample(rng, 200_000)
    x, y = x[:, 0], y[:, 0]
    # bivariate normal densities with correlation +-0.9 written out (not the bench's grid)
    s = 1 - 0.9**2
    p = sum(0.5 * np.exp(-(x * x - 2 * r * x * y + y * y) / (2 * s)) / (2 * np.pi * np.sqrt(s))
            for r in (0.9, -0.9))
    ratio = np.log(p) - stats.norm.logpdf(x) - stats.norm.logpdf(y)
    se = ratio.std() / math.sqrt(ratio.size)
    assert se < 0.003
    assert abs(ratio.mean() - tasks["X-mixture-1x1"].truth) < 5 * se
    # and the trapezoid rule has converged: a grid 1.5 times coarser agrees to 1e-9
    assert bench.mixture_x_mi(0.9, 12.0, 801) == pytest.approx(bench.mixture_x_mi(), abs=1e-9)


def test_rounded_normal_mi_from_scipy_rectangle_probabilities(bench):
    rho, step = 0.75, 0.5
    kmax = 14  # |v| > 7 sd: probability < 3e-12, absorbed by the outer cells
    edges = (np.arange(-kmax, kmax + 2) - 0.5) * step
    edges[0], edges[-1] = -40.0, 40.0
    gx, gy = np.meshgrid(edges, edges, indexing="ij")
    cdf = stats.multivariate_normal.cdf(
        np.stack([gx.ravel(), gy.ravel()], axis=1), mean=np.zeros(2), cov=bench.corr2(rho),
        abseps=1e-10, releps=1e-10).reshape(gx.shape)
    p = np.clip(np.diff(np.diff(cdf, axis=0), axis=1), 0.0, None)
    px, py = p.sum(1), p.sum(0)
    nz = p > 0
    ref = float(np.sum(p[nz] * np.log(p[nz] / np.outer(px, py)[nz])))
    assert bench.rounded_normal_mi(rho, step) == pytest.approx(ref, abs=2e-5)
    # the continuous limit: the MI lost to rounding shrinks like step^2 (0.0011 nats at
    # 0.1 sd) towards -0.5 ln(1 - rho^2)
    assert bench.rounded_normal_mi(rho, 0.05) == pytest.approx(
        -0.5 * math.log(1 - rho**2), abs=4e-4)


@pytest.mark.parametrize("dz, b", [(1, 0.8), (5, 0.8), (20, 0.8), (5, 0.0)])
def test_gaussian_cmi_truth_three_ways(bench, dz, b):
    cov = bench.cmi_cov(dz, b)
    exact = bench.gaussian_cmi(cov, [0], [1], range(2, 2 + dz))
    # partial correlation of x and y given z (Schur complement)
    s = cov[:2, :2] - cov[:2, 2:] @ np.linalg.solve(cov[2:, 2:], cov[2:, :2])
    r = s[0, 1] / math.sqrt(s[0, 0] * s[1, 1])
    assert exact == pytest.approx(-0.5 * math.log(1 - r**2), abs=1e-12)
    # given z, x = e_x + const and y = b e_x + e_y + const: 0.5 ln(1 + b^2)
    assert exact == pytest.approx(0.5 * math.log1p(b**2), abs=1e-12)
    # the covariance is that of the generative model
    rng = np.random.default_rng(dz)
    n = 200_000
    z = rng.standard_normal((n, dz))
    wz = z.sum(1) / math.sqrt(dz)
    x = wz + rng.standard_normal(n)
    y = b * x + wz + rng.standard_normal(n)
    emp = np.cov(np.column_stack([x, y, z]).T)
    # largest variance here is (1 + b)^2 + 1 + b^2 ~ 5; sd of a sample covariance of
    # order 5 / sqrt(n) = 0.011
    assert np.max(np.abs(emp - cov)) < 0.06


def test_transforms_are_strictly_increasing(bench):
    v = np.linspace(-40.0, 40.0, 400_001)
    for f in (bench.half_cube, bench.wiggly_x, bench.wiggly_y, np.arcsinh):
        assert np.all(np.diff(f(v)) > 0), f.__name__
    # Phi rounds to 1.0 above ~8 sd in float64; on the range a sample of 1e4 reaches
    # (|v| < 6 with probability 1 - 2e-5) it is strictly increasing at this spacing
    u = bench.normal_cdf(np.linspace(-6.0, 6.0, 20_001))
    assert np.all(np.diff(u) > 0)
    for f in (bench.BIMODAL_X, bench.BIMODAL_Y):
        assert np.all(np.diff(f(u)) > 0)


def test_bimodal_marginals_are_the_published_mixtures(tasks):
    x, y, _ = tasks["bimodal-1x1"].sample(np.random.default_rng(3), 20_000)

    def mix(weights, means):
        return lambda v: sum(w * special.ndtr(v - m) for w, m in zip(weights, means, strict=True))

    assert stats.kstest(x[:, 0], mix((0.3, 0.7), (0.0, 5.0))).pvalue > 1e-3
    assert stats.kstest(y[:, 0], mix((0.5, 0.5), (-1.0, 3.0))).pvalue > 1e-3
    # and not, say, a single normal of the same mean and variance
    assert stats.kstest(x[:, 0], "norm", args=(x.mean(), x.std())).pvalue < 1e-6


def test_student_and_cauchy_samplers_have_the_stated_laws(tasks):
    rng = np.random.default_rng(4)
    for df in (1, 2, 5):
        x, y, _ = tasks[f"student-1x1-df{df}"].sample(rng, 20_000)
        assert stats.kstest(x[:, 0], "t", args=(df,)).pvalue > 1e-3
        assert stats.kstest(y[:, 0], "t", args=(df,)).pvalue > 1e-3
    x, y, _ = tasks["cauchy-additive"].sample(rng, 20_000)
    assert stats.kstest(y[:, 0], "cauchy", args=(0.0, 2.0)).pvalue > 1e-3


def test_outlier_mixture_mi_agrees_with_monte_carlo(bench, tasks):
    # iid draws from the mixture law (not the task's sampler, which fixes the count):
    # 0.99 N(0, R(0.75)) + 0.01 N(0, 1e6^2 I), densities written out with scipy
    rng = np.random.default_rng(11)
    n, f, s = 400_000, 0.01, 1e6
    xy = rng.multivariate_normal([0.0, 0.0], [[1.0, 0.75], [0.75, 1.0]], size=n)
    out = rng.random(n) < f
    xy[out] = s * rng.standard_normal((int(out.sum()), 2))
    x, y = xy[:, 0], xy[:, 1]
    clean = stats.multivariate_normal([0.0, 0.0], [[1.0, 0.75], [0.75, 1.0]])
    joint = (1 - f) * clean.pdf(xy) + f * stats.norm.pdf(x, scale=s) * stats.norm.pdf(y, scale=s)
    px = (1 - f) * stats.norm.pdf(x) + f * stats.norm.pdf(x, scale=s)
    py = (1 - f) * stats.norm.pdf(y) + f * stats.norm.pdf(y, scale=s)
    ratio = np.log(joint) - np.log(px) - np.log(py)
    se = ratio.std() / math.sqrt(n)
    assert se < 0.002
    truth = tasks["outliers-1pct"].truth
    assert abs(ratio.mean() - truth) < 5 * se
    # and the clean truth it replaced is outside that band (0.052 lower)
    assert abs(ratio.mean() - tasks["normal-1x1"].truth) > 20 * se


def test_contaminated_tasks_keep_the_clean_truth_and_contaminate_as_stated(tasks):
    clean = tasks["normal-1x1"].truth
    assert tasks["glitch-1"].truth == clean
    x, y, _ = tasks["glitch-1"].sample(np.random.default_rng(0), 5000)
    assert np.sum(x == 1e6) == 1 and np.max(np.abs(y)) < 10
    x, y, _ = tasks["outliers-1pct"].sample(np.random.default_rng(0), 5000)
    assert 45 <= np.sum(np.abs(x) > 1e3) <= 50  # 50 rows at 1e6 sd: |v| < 1e3 has p 8e-4
    x, y, _ = tasks["rounded-0.5"].sample(np.random.default_rng(0), 5000)
    assert np.allclose(x / 0.5, np.round(x / 0.5), atol=1e-12, rtol=0)


def test_cli_refuses_bad_input_in_one_line_and_keeps_an_existing_out(bench, tmp_path, capsys):
    existing = tmp_path / "table.md"
    existing.write_text("mine")
    for argv in (["--tasks", "no-such-task"], ["--n", "5"], ["--seeds", "0"],
                 ["--out", str(existing)], ["--out", str(tmp_path / "no" / "t.md")]):
        assert bench.main(argv) == 2, argv
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("bench_mi_accuracy: "), argv
    assert existing.read_text() == "mine"
    with pytest.raises(SystemExit) as exc:
        bench.main(["--n", "many"])
    assert exc.value.code == 2
    assert capsys.readouterr().err.count("\n") == 1


def test_cli_writes_the_printed_table(bench, tmp_path, capsys):
    out = tmp_path / "table.md"
    assert bench.main(["--n", "300", "--seeds", "1", "--tasks", "normal-1x1",
                       "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert out.read_text() == printed
    row = next(line for line in printed.splitlines() if line.startswith("| normal-1x1 |"))
    # truth column, then the six estimators' cells
    assert "| 0.4133 |" in row and row.count("|") == 10


def test_a_warning_or_refusing_estimator_is_reported_not_fatal(bench, tasks, monkeypatch):
    # issue 27 lets defaults switch method with a warning or refuse: the table records it
    def fake(name, task, seed):
        def call(x, y, z):
            if name == "kde":
                raise ValueError("too many conditioning columns\nsecond line")
            if name == "histogram":
                warnings.warn("switched to ksg", UserWarning, stacklevel=1)
                return 0.5
            return 0.4
        return call

    monkeypatch.setattr(bench, "estimator", fake)
    names = ("kde", "histogram", "ksg")
    task = tasks["normal-1x1"]
    cells = bench.run_task(task, 100, 2, 8, names)
    assert cells["kde"].skipped == "refused (ValueError)"
    assert cells["kde"].notes == {"ValueError: too many conditioning columns"}
    assert cells["histogram"].value == 0.5 and len(cells["histogram"].estimates) == 2
    assert cells["histogram"].notes == {"UserWarning: switched to ksg"}
    assert not cells["ksg"].notes
    text = bench.render([(task, cells)], 100, (2, 1), names, (1.0, 1.0))
    row = next(line for line in text.splitlines() if line.startswith("| normal-1x1 | 1x1"))
    assert "refused (ValueError)" in row and "**0.500 (+0.087)** W" in row
    assert "- normal-1x1, histogram: UserWarning: switched to ksg" in text
    assert "- kde: 0/0; refused normal-1x1" in text
