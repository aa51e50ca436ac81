"""Bordered band matrices: lines' DOFs banded, bodies' DOFs a dense border (compiled).

A network's reduced matrices couple each line node to its neighbours (a band of
half-width w in the line DOFs) and every body DOF to its line ends (a border):

    A = [[B, E],      B (nf, nf) banded, E (nf, nb), F (nb, nf), D (nb, nb) dense
         [F, D]]

LU by the Schur complement, O(nf w^2 + nf w nb + nb^3): B = L U with threshold pivoting
(LAPACK's gbtf2 in numba loops), Y = B^-1 E, S = D - F Y factorized densely, so that
a factorization costs little more than the band's. Everything here is numba-compiled and
takes the parts as plain arrays: ``ab`` (3 w + 1, nf) in LAPACK's band storage
(A[i, j] = ab[2 w + i - j, j], the first w rows the pivoting's fill-in), ``E``, ``F``,
``D``; the factors overwrite them in place.
"""
import numpy as np
import scipy.sparse as sp
from numba import njit

PIVOT_THRESHOLD = 0.01  # a diagonal entry this share of its column's largest is a pivot


def band_storage(bandwidth, nf):
    """Zeroed band storage for an (nf, nf) band of half-width ``bandwidth``, column-major
    as LAPACK's (a column of the band contiguous: the LU's inner loops run along it)."""
    return np.zeros((3 * bandwidth + 1, nf), order="F")


@njit(cache=True, error_model="numpy")  # (no zero check per division)
def band_factor(ab, w, piv):
    """LU of the band in ``ab`` (kl = ku = w, in place; LAPACK gbtf2's loops) with threshold
    partial pivoting: a row swapped in only where the diagonal is below ``PIVOT_THRESHOLD``
    times the column's largest entry (HSL MA48's default; swaps widen U to up to 2 w
    superdiagonals, and a Newton matrix, nearly symmetric and positive definite, needs
    few), its swaps in piv (n + 1,), piv[n] the superdiagonals U has: False when a pivot
    is zero (singular)."""
    n = ab.shape[1]
    kv = 2 * w  # row of the diagonal
    for j in range(n):  # the fill-in rows start at zero
        for i in range(w):
            ab[i, j] = 0.0
    last = 0  # the last column the pivots so far reach
    upper = min(w, n - 1)
    for j in range(n):
        below = min(w, n - 1 - j)
        column = ab[:, j]  # (views: the loops below then run on contiguous memory)
        p, big = 0, abs(column[kv])
        for i in range(1, below + 1):
            if abs(column[kv + i]) > big:
                p, big = i, abs(column[kv + i])
        if abs(column[kv]) >= PIVOT_THRESHOLD * big:
            p = 0  # the diagonal is large enough: no swap, no fill-in
        piv[j] = j + p
        if big == 0.0:
            return False
        last = max(last, min(j + w + p, n - 1))
        upper = max(upper, last - j)
        if p:
            for c in range(j, last + 1):
                top, low = kv + j - c, kv + j + p - c
                ab[top, c], ab[low, c] = ab[low, c], ab[top, c]
        multipliers = column[kv + 1:kv + 1 + below]
        for i in range(below):
            multipliers[i] /= column[kv]
        for c in range(j + 1, last + 1):
            top = kv + j - c
            target = ab[top + 1:top + 1 + below, c]
            a = ab[top, c]
            if a != 0.0:
                for i in range(below):
                    target[i] -= multipliers[i] * a
    piv[n] = upper
    return True


@njit(cache=True, error_model="numpy")  # (no zero check per division)
def band_solve(ab, w, piv, b):
    """b <- A^-1 b (b (n,)) with the factors of :func:`band_factor` (U's back substitution
    over the superdiagonals it has: half the fill-in rows' work where nothing was swapped)."""
    n = ab.shape[1]
    kv, upper = 2 * w, piv[n]
    for j in range(n):
        p = piv[j]
        if p != j:
            b[j], b[p] = b[p], b[j]
        below = min(w, n - 1 - j)
        multipliers, rest, bj = ab[kv + 1:kv + 1 + below, j], b[j + 1:j + 1 + below], b[j]
        for i in range(below):
            rest[i] -= multipliers[i] * bj
    for j in range(n - 1, -1, -1):
        b[j] /= ab[kv, j]
        above = min(upper, j)
        column, rest, bj = ab[kv - above:kv, j], b[j - above:j], b[j]
        for i in range(above):
            rest[i] -= column[i] * bj


@njit(cache=True)
def band_solve_columns(ab, w, piv, B):
    """B <- A^-1 B, all columns at once (B (n, m), C order)."""
    n, m = B.shape
    kv, upper = 2 * w, piv[n]
    for j in range(n):
        p = piv[j]
        if p != j:
            for r in range(m):
                B[j, r], B[p, r] = B[p, r], B[j, r]
        for i in range(1, min(w, n - 1 - j) + 1):
            lij = ab[kv + i, j]
            if lij != 0.0:
                for r in range(m):
                    B[j + i, r] -= lij * B[j, r]
    for j in range(n - 1, -1, -1):
        d = 1.0 / ab[kv, j]
        for r in range(m):
            B[j, r] *= d
        for i in range(1, min(upper, j) + 1):
            uij = ab[kv - i, j]
            if uij != 0.0:
                for r in range(m):
                    B[j - i, r] -= uij * B[j, r]


@njit(cache=True)
def dense_factor(A, piv):
    """LU with partial pivoting of a small dense A (in place): False when singular."""
    n = A.shape[0]
    for j in range(n):
        p, big = j, abs(A[j, j])
        for i in range(j + 1, n):
            if abs(A[i, j]) > big:
                p, big = i, abs(A[i, j])
        piv[j] = p
        if big == 0.0:
            return False
        if p != j:
            for c in range(n):
                A[j, c], A[p, c] = A[p, c], A[j, c]
        for i in range(j + 1, n):
            A[i, j] /= A[j, j]
            for c in range(j + 1, n):
                A[i, c] -= A[i, j] * A[j, c]
    return True


@njit(cache=True)
def dense_solve(A, piv, b):
    """b <- A^-1 b (b (n,)) with the factors of :func:`dense_factor`."""
    n = A.shape[0]
    for j in range(n):  # the row swaps of the whole factorization first (LAPACK getrs)
        p = piv[j]
        if p != j:
            b[j], b[p] = b[p], b[j]
    for j in range(n):
        for i in range(j + 1, n):
            b[i] -= A[i, j] * b[j]
    for j in range(n - 1, -1, -1):
        b[j] /= A[j, j]
        for i in range(j):
            b[i] -= A[i, j] * b[j]


@njit(cache=True)
def factor(ab, w, E, F, D, piv_band, piv_schur):
    """Factorize [[B, E], [F, D]] in place: B's LU in ab (its swaps in piv_band, (nf + 1,):
    :func:`band_factor`), B^-1 E in E, the Schur complement D - F B^-1 E's LU in D (its
    swaps in piv_schur, (nb,)). False when B or the complement is singular."""
    if not band_factor(ab, w, piv_band):
        return False
    nb = D.shape[0]
    if nb == 0:
        return True
    band_solve_columns(ab, w, piv_band, E)
    nf = E.shape[0]
    for i in range(nb):
        for k in range(nf):
            f = F[i, k]
            if f != 0.0:  # F holds the few rows next to the bodies' line ends
                for j in range(nb):
                    D[i, j] -= f * E[k, j]
    return dense_factor(D, piv_schur)


@njit(cache=True)
def solve(ab, w, E, F, D, piv_band, piv_schur, b):
    """b <- A^-1 b with the factors of :func:`factor` (b (nf + nb,))."""
    nf, nb = E.shape[0], D.shape[0]
    top = b[:nf]
    band_solve(ab, w, piv_band, top)
    if nb == 0:
        return
    rest = b[nf:]
    for i in range(nb):
        s = 0.0
        for k in range(nf):
            if F[i, k] != 0.0:
                s += F[i, k] * top[k]
        rest[i] -= s
    dense_solve(D, piv_schur, rest)
    for k in range(nf):
        s = 0.0
        for j in range(nb):
            s += E[k, j] * rest[j]
        top[k] -= s


@njit(cache=True)
def matvec(ab, w, E, F, D, x, out):
    """out = A x for the unfactorized parts (ab with zero fill-in rows)."""
    nf, nb = E.shape[0], D.shape[0]
    kv = 2 * w
    for i in range(nf):
        s = 0.0
        for j in range(max(0, i - w), min(nf, i + w + 1)):
            s += ab[kv + i - j, j] * x[j]
        for j in range(nb):
            s += E[i, j] * x[nf + j]
        out[i] = s
    for i in range(nb):
        s = 0.0
        for k in range(nf):
            s += F[i, k] * x[k]
        for j in range(nb):
            s += D[i, j] * x[nf + j]
        out[nf + i] = s


def split(A, nf, w, n=None):
    """(ab, E, F, D) of a dense or sparse (n, n) matrix with nf banded rows (nothing of size
    n^2 is formed; A None: zero, of size ``n``); raises when the line part has entries
    outside the band of half-width w."""
    if A is None:
        return (band_storage(w, nf), np.zeros((nf, n - nf)), np.zeros((n - nf, nf)),
                np.zeros((n - nf, n - nf)))
    A = sp.csr_matrix(A)  # (no copy of a CSR matrix)
    n = A.shape[0]
    rows = np.repeat(np.arange(n), np.diff(A.indptr))
    cols, data = A.indices, A.data
    line_rows, line_cols = rows < nf, cols < nf
    band = line_rows & line_cols & (data != 0)
    if np.any(np.abs(rows[band] - cols[band]) > w):
        raise ValueError(f"bordered.split: the line part is wider than the band w = {w}")
    ab = band_storage(w, nf)
    np.add.at(ab, (2 * w + rows[band] - cols[band], cols[band]), data[band])
    E, F, D = np.zeros((nf, n - nf)), np.zeros((n - nf, nf)), np.zeros((n - nf, n - nf))
    for part, keep, r, c in ((E, line_rows & ~line_cols, 0, nf), (F, ~line_rows & line_cols, nf, 0),
                             (D, ~line_rows & ~line_cols, nf, nf)):
        np.add.at(part, (rows[keep] - r, cols[keep] - c), data[keep])
    return ab, E, F, D
