# Variants of section 8's rule tried against its false stops (docs/traction.md,
# "Where the false stops are"): the rise over 2 m instead of 1 m, a rise that
# must hold over the last two metres (the smaller of the two), and a floor on
# the present coefficient. Each beside the shipped rule (rho + 2 m x rise >= L).
#   python3 variants.py TUNE_DIR CHECK_DIR   (dump_rows output, README.md)
import os, sys
sys.path.insert(0, os.path.dirname(__file__))
from trend import prep, score, rise_per_m

def rise_before(t, i, back, span=1.0):
    # the rise per metre over the span that ends `back` metres before row i
    xs, j = t['x'], i
    while j > 0 and xs[i] - xs[j] < back:
        j -= 1
    return rise_per_m(t, j, span) if xs[i] - xs[j] >= back else 0.0

def carried(t, i, rise, L):
    return t['rho'][i] + 2.0 * max(0.0, rise) >= L

def rules():
    out = {}
    for L in (0.38, 0.42):
        out['shipped >= %.2f' % L] = lambda t, i, L=L: carried(t, i, rise_per_m(t, i), L)
        out['rise over 2 m >= %.2f' % L] = lambda t, i, L=L: carried(t, i, rise_per_m(t, i, 2.0), L)
        out['rise held 2 m >= %.2f' % L] = lambda t, i, L=L: carried(t, i, min(rise_per_m(t, i), rise_before(t, i, 1.0)), L)
        for F in (0.20, 0.25, 0.30):
            out['rho >= %.2f and shipped >= %.2f' % (F, L)] = (
                lambda t, i, L=L, F=F: t['rho'][i] >= F and carried(t, i, rise_per_m(t, i), L))
    return out

if __name__ == '__main__':
    tune, check = prep(sys.argv[1]), prep(sys.argv[2])
    for name, rule in rules().items():
        print('%-34s T: %s | check tuning: %s | check held: %s' %
              (name, score(tune, rule, False), score(check, rule, False), score(check, rule, True)), flush=True)
