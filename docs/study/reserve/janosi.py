# The soil's remaining thrust from the slip alone (issue 14: "the pull the soil can
# still give"): with Janosi's shear curve and a fixed K/L, the thrust mobilised at
# slip s is a fraction f(s) of the capacity, so the reserve over the weight is
# (sum T / (r sum W)) (1 / f(s) - 1). Printed: its ratio to the simulator's true
# reserve, and stop rules on it (docs/traction.md, "Limits").
#   python3 janosi.py TUNE_DIR CHECK_DIR   (dump_rows output, README.md)
import math, os, sys
sys.path.insert(0, os.path.dirname(__file__))
from trend import prep, score, rise_per_m
from ev import rmed
G, R = 1.62, 0.15
def f_janosi(s, kl):
    # fraction of the shear capacity mobilised at slip s, K/L = kl
    if s <= 1e-4: return 0.0
    a = s / kl
    return 1.0 - (1.0 - math.exp(-a)) / a
def add_est(trs, kl):
    for t in trs:
        est = []
        for r in t['rows']:
            s = r['slip']
            T = sum(r['T%d' % w] for w in range(6)) / R
            W = sum(r['W%d' % w] for w in range(6))
            f = f_janosi(s, kl) if s > -1 else 0.0
            est.append((T / W) * (1.0 / f - 1.0) if f > 0.02 else 10.0)
        t['res'] = rmed(est)
        t['true_res'] = [(r['dpmax'] - t['mass']*G*math.sin(math.radians(r['pitch_deg'])))/(t['mass']*G) if not math.isnan(r['dpmax']) else float('nan') for r in t['rows']]
tune, check = prep(sys.argv[1]), prep(sys.argv[2])
for kl in (0.05, 0.1, 0.2, 0.4):
    add_est(tune, kl); add_est(check, kl)
    # correlation-ish: median ratio est/true where true in (0.02, 0.5)
    ratios = []
    for t in tune:
        for a, b in zip(t['res'], t['true_res']):
            if 0.05 < b < 0.5 and a < 5: ratios.append(a / b)
    ratios.sort()
    q = lambda p: ratios[int(p*(len(ratios)-1))]
    print('K/L %.2f est/true quartiles %.2f %.2f %.2f (n=%d)' % (kl, q(0.25), q(0.5), q(0.75), len(ratios)))
    for th in (0.05, 0.10, 0.15, 0.2):
        rule = lambda t, i, th=th: t['res'][i] < th
        print('   res<%.2f T: %s | C: %s | H: %s' % (th, score(tune, rule, False), score(check, rule, False), score(check, rule, True)), flush=True)
