"""Expected calibration error of (confidence, right) pairs, as `vref eval`
computes it (docs/method.md, "Choices where ALGORITHMS.md leaves room"):
equal-width bins of confidence on [0, 1], confidence 1 in the last, the sum
over bins of the bin's share times |mean confidence - fraction right|.
Shared by the tools that choose constants from answer files."""


def ece(pairs, bins=10):
    count, conf, right = [0] * bins, [0.0] * bins, [0] * bins
    for c, ok in pairs:
        k = min(int(c * bins), bins - 1)
        count[k] += 1
        conf[k] += c
        right[k] += bool(ok)
    total = sum(count)
    return sum(abs(conf[k] - right[k]) / total for k in range(bins) if count[k])
