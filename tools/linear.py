"""`a x = b` for the small dense systems of the tools' logistic fits
(fit-calibration.py, featureless-recalibration.py)."""


def solve(a, b):
    """Solves a x = b (small, dense) by Gaussian elimination with partial
    pivoting."""
    n = len(b)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        for r in range(n):
            if r != c and m[c][c] != 0:
                f = m[r][c] / m[c][c]
                m[r] = [x - f * y for x, y in zip(m[r], m[c])]
    return [m[i][n] / m[i][i] for i in range(n)]
