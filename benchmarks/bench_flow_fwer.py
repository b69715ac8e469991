"""Family-wise error and power of the transfer-entropy map (issue 21, its FWER question).

Run: /work/main/.venv/bin/python benchmarks/bench_flow_fwer.py [--quick] [--part ...]

Parts (all on independent or planted AR(1) series, n = 500 rows, history 1, Gaussian
estimator; every map's data drawn once and shared by the procedures compared):

``fwer``
    Fraction of maps with at least one significant cell when no link exists (2 000
    maps per size; --quick: 300), for maps of 2, 12, 48 and 100 cells (2 x 1, 3 x 2,
    4 x 4 and 5 x 5 series x lags), at family-wise alpha = 0.05 and 0.10, 49
    surrogates (and 199 for the 48-cell map), three procedures on the same maps:
    ``old``, the map before this change (the target's residual rotated against the
    sources' residuals, shifts drawn uniformly from ``[m, n - m]`` with m the
    Politis-White block length; re-implemented below); ``random``, the sources
    rotated and residualised like the originals but the shifts still drawn from
    ``[m, n - m]``; ``new``, :func:`modalinfo.information.transfer_entropy_map` now
    (the sources rotated, the shifts on a lattice with the original at 0,
    :func:`modalinfo.information.flow.surrogate_shifts`). With N surrogates an exact
    test at level alpha rejects with probability ``floor(alpha (N + 1)) / (N + 1)``
    (0.04 at 0.05 with 49 surrogates); the standard error is that of a binomial
    fraction at that level.
``mechanism``
    The null scale of one cell, ``n rho^2`` (about 1 for a correlation test), and the
    0.9 quantile of the largest of the 48 cells of a 4 x 4 map, for the original
    statistic (the null itself, independent series) and for the two surrogate designs
    at fixed shifts (150 and n/2 + 3), over 3 000 maps (--quick 400).
``power``
    Recall and spurious links of the planted 6-series VAR network of
    ``tests/information/test_flow.py`` (3 links, coupling 0.4 as there and a weak
    0.15), n = 1 000, 6 lags, alpha = 0.05, 99 surrogates, 40 seeds: ``old``, ``new``
    single-step and ``new`` step-down.

``scales``
    Maps whose cells have different null scales: 4 series with AR(1) coefficients
    0.2, 0.5, 0.8, 0.95 and history 0 (the targets are not whitened, so a cell's null
    variance grows with ``(1 + a_i a_j) / (1 - a_i a_j)``), and for contrast 4 series
    at 0.95 with history 1 (correlation time ~40 rows against a lattice spacing of 9):
    the FWER, and where the map's maximum falls under the null (source x target
    fractions), 1 000 maps (--quick 100), 4 lags, 49 surrogates.
``restricted``
    Maps restricted by ``candidates="radial"`` (issue 30 item 3): independent AR(1)
    series labelled Z2.. (9 series, width 1; 20 series, widths 1 and 2), 2 lags, 49
    surrogates, 2 000 maps each (--quick 200), step-down and single-step: the fraction
    of maps with a significant cell against the exact level.
``selection``
    The same question for :func:`modalinfo.information.select_inputs`: a target
    AR(1) (0.7) and 3 independent AR(1) series, 500 frames (496 rows), lags 0..3
    (16 candidates), horizon 1, 49 surrogates; the first step picks the target's own
    last value (the whole true model), so a second input is a family-wise error of
    the second step; 16 000 runs (--quick 1 000) at alpha = 0.05 and 0.1, on the same
    data: ``old``, the test before it was repaired (the target's residual rotated
    against the candidates' residuals, shifts drawn per step from ``[m, n - m]``;
    re-implemented below, same p-values as the old code from the same seed), and
    ``new``, :func:`select_inputs` now (the candidates rotated and residualised like
    the originals, lattice shifts, as the map). Then the same for short slow series
    (200 frames, AR(1) 0.9; 2 000 runs, --quick 125), where the lattice spacing (3
    rows) is below the correlation time.

Single-threaded (BLAS pools set to 1): the shared machine's multi-threaded BLAS is
slower under load.
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from scipy.signal import lfilter  # noqa: E402

from modalinfo.information import flow as flow_mod  # noqa: E402
from modalinfo.information import transfer_entropy_map  # noqa: E402
from modalinfo.information.resampling import auto_block_length as _auto_block  # noqa: E402

N_ROWS = 500
AR = 0.7
SIZES = ((2, 1), (3, 2), (4, 4), (5, 5))  # (series, lags): 2, 12, 48, 100 cells


def ar1_series(rng: np.random.Generator, n: int, s: int, a: float = AR) -> np.ndarray:
    """``(n, s)`` independent AR(1) series (100 burn-in samples dropped)."""
    return lfilter([1.0], [1.0, -a], rng.standard_normal((n + 100, s)), axis=0)[100:]


def old_map_pvalues(x: np.ndarray, lags: int, n_surrogates: int, seed: int) -> np.ndarray:
    """Single-step p-values of the map before this change (the target residual rotated).

    The previous ``flow._gaussian_map``: per target, the residual r of the target on
    its history is rotated by s against the residualised sources R; shifts uniform on
    ``[min_shift, n - min_shift]``; p = (1 + #{null max >= TE}) / (1 + N).
    """
    lag = np.arange(1, lags + 1)
    T, S = x.shape
    t0 = max(lags, 1)
    n = T - t0
    rng = np.random.default_rng(seed)
    shift0 = min(_auto_block(x[t0:]), n // 2)
    shifts = rng.integers(shift0, n - shift0 + 1, size=n_surrogates)
    C = flow_mod._lagged_block(x, lag, t0)
    Cc = C - C.mean(axis=0)
    rows = (np.arange(n)[None, :] - shifts[:, None]) % n
    te = np.full((S, S * lags), -np.inf)
    null_max = np.zeros(n_surrogates)
    for i in range(S):
        q = flow_mod._history_basis(flow_mod._history(x[:, i], 1, t0))
        r = x[t0:, i] - x[t0:, i].mean()
        r = r - q @ (q.T @ r)
        R = Cc - q @ (q.T @ Cc)
        ok = np.ones(S * lags, bool)
        ok[i::S] = False
        cn = np.sqrt(np.einsum("ij,ij->j", R, R))[ok]
        rn = math.sqrt(float(r @ r))
        te[i, ok] = ((r @ R[:, ok]) / (cn * rn)) ** 2
        null_max = np.maximum(null_max, (((r[rows] @ R[:, ok]) / (cn * rn)) ** 2).max(axis=1))
    tmax = te.max()
    return (1 + np.count_nonzero(null_max >= tmax)) / (1 + n_surrogates)


def random_shift_pvalue(x: np.ndarray, lags: int, n_surrogates: int, seed: int) -> float:
    """Single-step p-value of the map with the sources rotated (as now) but the shifts
    drawn uniformly from ``[m, n - m]`` (m the Politis-White block length), as before."""
    t0 = lags
    n = x.shape[0] - t0
    rng = np.random.default_rng(seed)
    shift0 = min(_auto_block(x[t0:]), n // 2)
    shifts = rng.integers(shift0, n - shift0 + 1, size=n_surrogates)
    te, null = flow_mod._gaussian_map(x, np.arange(1, lags + 1), 1, t0, shifts)
    off = ~np.eye(x.shape[1], dtype=bool)
    return (1 + np.count_nonzero(null[:, off].reshape(n_surrogates, -1).max(axis=1)
                                 >= te[off].max())) / (1 + n_surrogates)


def part_fwer(n_maps: int, surrogates: tuple) -> None:
    print(f"\n## FWER under independence (n = {N_ROWS}, AR({AR}), history 1, {n_maps} maps)\n")
    print("| cells | S x L | N | alpha | exact level | old | random | new | se |")
    print("|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    for n_surr, sizes in surrogates:
        for S, L in sizes:
            rng = np.random.default_rng(1000 * S + L + n_surr)
            p = {"old": [], "random": [], "new": []}
            t = time.perf_counter()
            for m in range(n_maps):
                x = ar1_series(rng, N_ROWS, S)
                p["old"].append(old_map_pvalues(x, L, n_surr, seed=m))
                p["random"].append(random_shift_pvalue(x, L, n_surr, seed=m))
                res = transfer_entropy_map(x, lags=L, n_surrogates=n_surr, seed=m,
                                           alpha=0.1)
                p["new"].append(np.nanmin(res.pvalue))
            for alpha in (0.05, 0.10):
                exact = math.floor(alpha * (n_surr + 1) + 1e-9) / (n_surr + 1)
                se = math.sqrt(exact * (1 - exact) / n_maps)
                cols = " | ".join(f"{np.mean(np.array(v) <= alpha + 1e-12):.4f}"
                                  for v in p.values())
                print(f"| {S * (S - 1) * L} | {S} x {L} | {n_surr} | {alpha:.2f} | {exact:.3f} "
                      f"| {cols} | {se:.4f} |", flush=True)
            print(f"<!-- {S}x{L} N={n_surr}: {time.perf_counter() - t:.0f} s -->", flush=True)


def part_mechanism(n_maps: int) -> None:
    S, L, hist = 4, 4, 1
    lags = np.arange(1, L + 1)
    n = N_ROWS - L
    fixed = np.array([150, n // 2 + 3])
    rng = np.random.default_rng(21)
    orig, trot, srot = [], [], []
    for _ in range(n_maps):
        x = ar1_series(rng, N_ROWS, S)
        C = flow_mod._lagged_block(x, lags, L)
        Cc = C - C.mean(axis=0)
        o = np.zeros((S, S * L))
        tr = np.zeros((fixed.size, S, S * L))
        sr = np.zeros((fixed.size, S, S * L))
        for i in range(S):
            q = flow_mod._history_basis(flow_mod._history(x[:, i], hist, L))
            r = x[L:, i] - x[L:, i].mean()
            r = r - q @ (q.T @ r)
            R = Cc - q @ (q.T @ Cc)
            rn, cn = math.sqrt(r @ r), np.sqrt(np.einsum("ij,ij->j", R, R))
            o[i] = ((r @ R) / (cn * rn)) ** 2
            for k, s in enumerate(fixed):
                tr[k, i] = ((np.roll(r, s) @ R) / (cn * rn)) ** 2
                Rs = np.roll(Cc, s, axis=0)
                Rs = Rs - q @ (q.T @ Rs)
                sr[k, i] = ((r @ Rs) / (np.sqrt(np.einsum("ij,ij->j", Rs, Rs)) * rn)) ** 2
            o[i, i::S] = 0
            tr[:, i, i::S] = 0
            sr[:, i, i::S] = 0
        orig.append(o.ravel() * n)
        trot.append(tr.reshape(fixed.size, -1) * n)
        srot.append(sr.reshape(fixed.size, -1) * n)
    orig, trot, srot = np.array(orig), np.array(trot), np.array(srot)
    m0 = orig.max(axis=1)
    q0 = np.quantile(m0, 0.9)
    per_map = orig.sum(axis=1) / 48
    se_mean = np.std(per_map) / math.sqrt(per_map.size)
    print(f"\n## Mechanism: null scale of a cell and the 48-cell maximum ({n_maps} maps, "
          f"4 x 4, n = {n})\n")
    print(f"The null itself (shift 0): mean n rho^2 per cell {orig[orig > 0].mean():.4f} "
          f"(+- {se_mean:.4f}; an exact partial-correlation test: n/(n-2) = "
          f"{n / (n - 2):.4f}); 0.9 quantile of the 48-cell maximum {q0:.3f}.\n")
    print("| surrogate | shift | mean n rho^2 per cell | max-48 q0.9 | P(null max > it) |")
    print("|---|---:|---:|---:|---:|")
    for name, v in (("target residual rotated (old)", trot), ("source rotated (new)", srot)):
        for k, s in enumerate(fixed):
            mk = v[:, k].max(axis=1)
            qk = np.quantile(mk, 0.9)
            print(f"| {name} | {s} | {v[:, k][v[:, k] > 0].mean():.4f} | {qk:.3f} | "
                  f"{np.mean(m0 > qk):.4f} |", flush=True)


def planted(n: int, seed: int, c: float = 0.4) -> np.ndarray:
    """The planted network of tests/information/test_flow.py (m0->m1 lag 2, m4->m1 lag 1,
    m2->m3 lag 4)."""
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((n + 100, 6))
    x = np.zeros_like(e)
    for t in range(5, n + 100):
        for j in (0, 2, 4):
            x[t, j] = 0.3 * x[t - 1, j] + e[t, j]
        x[t, 5] = 0.5 * x[t - 1, 5] + e[t, 5]
        x[t, 1] = 0.5 * x[t - 1, 1] + c * x[t - 2, 0] + c * x[t - 1, 4] + e[t, 1]
        x[t, 3] = 0.5 * x[t - 1, 3] + c * x[t - 4, 2] + e[t, 3]
    return x[100:]


def _old_pvalues_all(x, lags, n_surrogates, seed):
    """Per-cell single-step p-values of the old procedure, (S, S, L)."""
    lag = np.arange(1, lags + 1)
    T, S = x.shape
    t0 = lags
    n = T - t0
    rng = np.random.default_rng(seed)
    shift0 = min(_auto_block(x[t0:]), n // 2)
    shifts = rng.integers(shift0, n - shift0 + 1, size=n_surrogates)
    C = flow_mod._lagged_block(x, lag, t0)
    Cc = C - C.mean(axis=0)
    rows = (np.arange(n)[None, :] - shifts[:, None]) % n
    te = np.zeros((S, S, lags))
    null_max = np.zeros(n_surrogates)
    for i in range(S):
        q = flow_mod._history_basis(flow_mod._history(x[:, i], 1, t0))
        r = x[t0:, i] - x[t0:, i].mean()
        r = r - q @ (q.T @ r)
        R = Cc - q @ (q.T @ Cc)
        ok = np.ones(S * lags, bool)
        ok[i::S] = False
        cn = np.sqrt(np.einsum("ij,ij->j", R, R))
        rn = math.sqrt(float(r @ r))
        rho2 = np.where(ok, ((r @ R) / (cn * rn)) ** 2, 0.0)
        te[:, i, :] = rho2.reshape(lags, S).T
        null_max = np.maximum(null_max, (((r[rows] @ R[:, ok]) / (cn[ok] * rn)) ** 2).max(axis=1))
    p = (1 + (null_max[None, None, None, :] >= te[..., None]).sum(-1)) / (1 + n_surrogates)
    p[np.eye(S, dtype=bool)] = np.nan
    return p


def part_power(n_seeds: int) -> None:
    links = {(0, 1, 2), (4, 1, 1), (2, 3, 4)}  # (source, target, lag)
    n, lags, alpha, n_surr = 1000, 6, 0.05, 99
    for c in (0.4, 0.15):
        _power(n_seeds, n, lags, alpha, n_surr, links, c)


def _power(n_seeds, n, lags, alpha, n_surr, links, c):
    counts = {k: [0, 0, 0] for k in ("old", "new single-step", "new step-down")}
    for seed in range(n_seeds):
        x = planted(n, 500 + seed, c)
        pv = {"old": _old_pvalues_all(x, lags, n_surr, seed)}
        for adj in ("single-step", "step-down"):
            pv[f"new {adj}"] = transfer_entropy_map(x, lags=lags, n_surrogates=n_surr,
                                                    alpha=alpha, adjust=adj, seed=seed).pvalue
        for k, p in pv.items():
            sig = np.nan_to_num(p, nan=2.0) <= alpha
            hit = sum(bool(sig[j, i, lag - 1]) for j, i, lag in links)
            pairs = {(j, i) for j, i, _ in links}
            spurious = sum(1 for j, i in zip(*np.nonzero(sig.any(axis=2)), strict=True)
                           if (j, i) not in pairs)
            counts[k][0] += hit
            counts[k][1] += spurious
            counts[k][2] += bool(spurious)
    print(f"\n## Power on the planted network (6 series, 3 links of coupling {c}, n = {n}, "
          f"lags 1..{lags}, alpha = {alpha}, {n_surr} surrogates, {n_seeds} seeds)\n")
    print("| procedure | recall (planted cell significant) | spurious pairs | maps with a "
          "spurious pair |")
    print("|---|---:|---:|---:|")
    for k, (hit, spur, maps) in counts.items():
        print(f"| {k} | {hit / (3 * n_seeds):.3f} | {spur} | {maps} / {n_seeds} |")


def part_scales(n_maps: int) -> None:
    for coefs, hist in (((0.2, 0.5, 0.8, 0.95), 0), ((0.95,) * 4, 1)):
        rng = np.random.default_rng(31)
        hits = {0.05: 0, 0.1: 0}
        where = np.zeros((4, 4))
        for m in range(n_maps):
            e = rng.standard_normal((N_ROWS + 100, 4))
            x = np.column_stack([lfilter([1.0], [1.0, -a], e[:, j])
                                 for j, a in enumerate(coefs)])[100:]
            res = transfer_entropy_map(x, lags=4, history=hist, n_surrogates=49, seed=m)
            for alpha in hits:
                hits[alpha] += bool(np.nanmin(res.pvalue) <= alpha + 1e-12)
            top = np.unravel_index(np.nanargmax(res.te), res.te.shape)
            where[top[0], top[1]] += 1
        print(f"\n## Null scales: AR coefficients {coefs}, history {hist} ({n_maps} maps)\n")
        print(f"FWER at 0.05 (exact 0.040): {hits[0.05] / n_maps:.3f}; at 0.10: "
              f"{hits[0.1] / n_maps:.3f}. Where the null map's maximum falls (rows source, "
              "columns target):\n")
        for row in where / n_maps:
            print("    " + " ".join(f"{v:.3f}" for v in row))


def old_selection_pvalues(x: np.ndarray, max_lag: int, n_surrogates: int, seed: int
                          ) -> tuple[float, float]:
    """p-values of the first two greedy steps of ``select_inputs`` before this change.

    Target column 0, horizon 1, the Gaussian direct path (fewer than 64 surrogates):
    at each step the target's residual is rotated against the candidates' residuals,
    with shifts drawn anew per step uniformly from ``[m, n - m]`` (m the Politis-White
    block length of the target); the same draws from the same seed as the old code.
    """
    from modalinfo.information.selection import (
        _gauss_gains,
        _unit_columns,
        lagged_candidates,
        unit_candidates,
    )

    rng = np.random.default_rng(seed)
    origins, C, _ = lagged_candidates(x, 1, max_lag)
    y = x[origins + 1, 0]
    n = y.size
    shift0 = min(_auto_block(y[:, None]), n // 2)
    R, alive = unit_candidates(C)
    r = _unit_columns(y[:, None])[0][:, 0].copy()
    out = []
    for _ in range(2):
        shifts = rng.integers(shift0, n - shift0 + 1, size=n_surrogates)
        gains = _gauss_gains(r, R, alive)
        best = int(np.argmax(np.where(alive, gains, -np.inf)))
        cn = np.sqrt(np.einsum("ij,ij->j", R, R))
        ok = alive & (cn > 0)
        xc = r[(np.arange(n)[None, :] - shifts[:, None]) % n] @ R[:, ok]
        rho = xc / (cn[ok][None, :] * math.sqrt(float(r @ r)))
        null = (-0.5 * np.log(np.maximum(1.0 - rho * rho, 1e-15))).max(axis=1)
        out.append((1.0 + np.count_nonzero(null >= gains[best])) / (1.0 + n_surrogates))
        q = R[:, best] / math.sqrt(float(R[:, best] @ R[:, best]))
        r -= q * float(q @ r)
        R -= np.outer(q, q @ R)
        alive[best] = False
        alive &= np.sqrt(np.einsum("ij,ij->j", R, R)) > 1e-6
    return out[0], out[1]


def part_selection(n_runs: int) -> None:
    from modalinfo.information import select_inputs

    alphas = (0.05, 0.1)
    # (frames, AR coefficient, runs): the map's series, and short slow ones whose
    # correlation time (~20 rows) exceeds the lattice spacing (196 // 50 = 3 rows)
    for frames, coef, runs in ((N_ROWS, AR, n_runs), (200, 0.9, max(n_runs // 8, 100))):
        rng = np.random.default_rng(9)
        extra = {"old": dict.fromkeys(alphas, 0), "new": dict.fromkeys(alphas, 0)}
        first_own = 0
        for k in range(runs):
            x = ar1_series(rng, frames, 4, coef)
            # one search at the larger alpha: the first step always passes (p = 1/50,
            # the target's own last value), and the same seed gives the same surrogates
            # at any alpha, so the second step's p-value decides both levels
            r = select_inputs(x, 0, horizon=1, max_lag=4, alpha=max(alphas), max_inputs=2,
                              n_surrogates=49, intervals=False, seed=k)
            first_own += bool(r.inputs) and (r.inputs[0].source, r.inputs[0].lag) == (0, 0)
            p_new = r.inputs[1].pvalue if len(r.inputs) > 1 else r.last_pvalue
            p_old = old_selection_pvalues(x, 4, 49, k)[1]
            for alpha in alphas:
                extra["new"][alpha] += p_new <= alpha + 1e-12
                extra["old"][alpha] += p_old <= alpha + 1e-12
        print(f"\n## select_inputs: a spurious second input ({frames} frames, AR({coef}), "
              f"{runs} runs, 16 candidates, first input the target's last value in "
              f"{first_own / runs:.3f})\n")
        print("| alpha | exact level | old | new | se |")
        print("|---:|---:|---:|---:|---:|")
        for alpha in alphas:
            level = math.floor(alpha * 50 + 1e-9) / 50
            print(f"| {alpha:.2f} | {level:.3f} | {extra['old'][alpha] / runs:.4f} | "
                  f"{extra['new'][alpha] / runs:.4f} | "
                  f"{math.sqrt(level * (1 - level) / runs):.4f} |", flush=True)


def part_restricted(n_maps: int) -> None:
    """FWER of maps restricted by ``candidates="radial"`` (issue 30 item 3)."""
    from modalinfo.telemetry import ModalLog

    print(f"\n## FWER over the restricted family (candidates='radial', n = {N_ROWS}, "
          f"AR({AR}), history 1, 49 surrogates, {n_maps} maps)\n")
    print("| series | width | cells | alpha | exact level | step-down | single-step | se |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|")
    for S, width in ((9, 1), (20, 1), (20, 2)):
        rng = np.random.default_rng(7000 + S + width)
        p = {"step-down": [], "single-step": []}
        cells = 0
        for m in range(n_maps):
            log = ModalLog(ar1_series(rng, N_ROWS, S), modes=list(range(2, 2 + S)), rate=1.0)
            for adjust in p:
                res = transfer_entropy_map(log, lags=2, n_surrogates=49, seed=m,
                                           candidates="radial", radial_width=width,
                                           adjust=adjust)
                p[adjust].append(np.nanmin(res.pvalue))
            cells = int(np.count_nonzero(~np.isnan(res.pvalue)))
        for alpha in (0.05, 0.10):
            exact = math.floor(alpha * 50 + 1e-9) / 50
            se = math.sqrt(exact * (1 - exact) / n_maps)
            cols = " | ".join(f"{np.mean(np.array(v) <= alpha + 1e-12):.4f}" for v in p.values())
            print(f"| {S} | {width} | {cells} | {alpha:.2f} | {exact:.3f} | {cols} | {se:.4f} |",
                  flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer maps")
    ap.add_argument("--part", nargs="+", default=["mechanism", "fwer", "power"],
                    choices=["mechanism", "fwer", "power", "scales", "selection",
                             "restricted"])
    ap.add_argument("--maps", type=int, default=None, help="maps per FWER cell")
    args = ap.parse_args()
    n_maps = args.maps or (300 if args.quick else 2000)
    t = time.perf_counter()
    if "mechanism" in args.part:
        part_mechanism(400 if args.quick else 3000)
    if "fwer" in args.part:
        part_fwer(n_maps, ((49, SIZES),) if args.quick else ((49, SIZES), (199, ((4, 4),))))
    if "power" in args.part:
        part_power(10 if args.quick else 40)
    if "scales" in args.part:
        part_scales(100 if args.quick else 1000)
    if "selection" in args.part:
        part_selection(1000 if args.quick else 16000)
    if "restricted" in args.part:
        part_restricted(args.maps or (200 if args.quick else 2000))
    print(f"\n<!-- total {time.perf_counter() - t:.0f} s -->")


if __name__ == "__main__":
    main()
