import csv, glob, os, statistics as st
HELD = {'one-side', 'drawn-soil'}
def load(d):
    trs = []
    for p in sorted(glob.glob(d + '/*.csv')):
        with open(p) as f:
            meta = dict(kv.split('=', 1) for kv in f.readline()[2:].split())
            rows = list(csv.DictReader(f))
        R = []
        for r in rows:
            if r['phase'] != 'drive': continue
            R.append({k: (float(v) if k != 'phase' else v) for k, v in r.items()})
        trs.append(dict(name=os.path.basename(p)[:-4], fam=meta['family'], emb=meta['embedded'] == '1',
                        ex=float(meta['embed_x']), et=float(meta['embed_t']), mass=float(meta['mass']),
                        slope=float(meta['slope']), rows=R))
    return trs
