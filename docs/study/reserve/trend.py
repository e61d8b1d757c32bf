# The scan behind section 8's default (docs/traction.md, "How the levels were
# chosen"): the motion-resistance coefficient rho = (sum T/r - sum DP)/sum W,
# its 5-sample running median, carried D metres ahead along its rise over the
# last metre (window starts before x = 1 m give no trend), against a stop
# level L; alone and with the 45 mm sinkage level beside it.
#   python3 trend.py TUNE_DIR [CHECK_DIR]
# TUNE_DIR: dump_rows output of the seed the choice is made on (its tuning
# families only: column T); CHECK_DIR: another seed, looked at afterwards.
import math, sys, os
sys.path.insert(0, os.path.dirname(__file__))
from load import load, HELD
from ev import rmed
G, R = 1.62, 0.15

def prep(d):
    trs = load(d)
    for t in trs:
        rows = t['rows']
        rf = [(r['dpmax'] - t['mass'] * G * math.sin(math.radians(r['pitch_deg']))) / (t['mass'] * G)
              for r in rows if not math.isnan(r['dpmax'])]
        t['minrf'] = min(rf) if rf else 1.0
        t['x'] = [r['x'] for r in rows]
        t['rho'] = rmed([(sum(r['T%d' % w] for w in range(6)) / R - sum(r['DP%d' % w] for w in range(6)))
                         / sum(r['W%d' % w] for w in range(6)) for r in rows])
        t['z'] = rmed([max(r['z%d' % w] for w in range(6)) for r in rows])
    return trs

def rise_per_m(t, i, span=1.0, x0=1.0):
    xs, j = t['x'], i
    while j > 0 and xs[i] - xs[j] < span:
        j -= 1
    if xs[j] < x0 or xs[i] - xs[j] < span:
        return 0.0
    return (t['rho'][i] - t['rho'][j]) / (xs[i] - xs[j])

def score(trs, rule, held):
    clear = fs = nm = nms = emb = bef = a1 = 0
    leads = []
    for t in trs:
        if (t['fam'] in HELD) != held:
            continue
        stop = next((t['x'][i] for i in range(5, len(t['rows'])) if rule(t, i)), None)
        if t['emb']:
            emb += 1
            lead = (t['ex'] - stop) if stop is not None else 0.0
            leads.append(lead)
            if stop is not None and stop < t['ex']:
                bef += 1
                a1 += lead >= 1
        elif t['minrf'] < 0.05:
            nm += 1; nms += stop is not None
        else:
            clear += 1; fs += stop is not None
    leads.sort()
    med = leads[len(leads) // 2] if leads else 0.0
    return 'false %2d/%2d near-miss %2d/%2d before %2d/%2d >=1m %2d lead %.2f' % (fs, clear, nms, nm, bef, emb, a1, med)

if __name__ == '__main__':
    tune = prep(sys.argv[1])
    check = prep(sys.argv[2]) if len(sys.argv) > 2 else None
    for with_z in (False, True):
        for L in (0.34, 0.38, 0.42):
            for D in (0.0, 0.5, 1.0, 2.0):
                rule = (lambda t, i, L=L, D=D, z=with_z:
                        t['rho'][i] + D * max(0.0, rise_per_m(t, i)) >= L or (z and t['z'][i] >= 0.045))
                name = '%srho+%.1f*rise>=%.2f' % ('z45|' if with_z else '', D, L)
                out = [name, 'T: ' + score(tune, rule, False)]
                if check:
                    out += ['check tuning: ' + score(check, rule, False), 'check held: ' + score(check, rule, True)]
                print(' | '.join(out))
