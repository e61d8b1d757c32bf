import sys; sys.path.insert(0, __import__('os').path.dirname(__file__))
from load import *
R = 0.15
def rmed(vals, k=5):
    out=[]
    for i in range(len(vals)):
        w = sorted(vals[max(0,i-k+1):i+1]); out.append(w[len(w)//2])
    return out
def signals(t):
    rows = t['rows']
    S = {}
    S['zest'] = [max(r['z%d'%w] for w in range(6)) for r in rows]
    S['truez'] = [r['true_z_mm']/1000 for r in rows]
    S['slip'] = [r['slip'] if r['slip']>-5 else 0 for r in rows]
    S['umax'] = [max(r['T%d'%w]/(R*r['W%d'%w]) for w in range(6)) for r in rows]
    S['umean'] = [sum(r['T%d'%w] for w in range(6))/(R*sum(r['W%d'%w] for w in range(6))) for r in rows]
    S['irat'] = [max(r['I%d'%w]/r['Imax%d'%w] if r['Imax%d'%w]>0 else 0 for w in range(6)) for r in rows]
    return {k: rmed(v) for k, v in S.items()}
def evaluate(trs, sig, level, held=False):
    fs=0; nord=0; leads=[]; before=0; nemb=0; ahead1=0
    for t in trs:
        if (t['fam'] in HELD) != held: continue
        v = t['sig'][sig]; xs=[r['x'] for r in t['rows']]
        stop=None
        for i,(x,s) in enumerate(zip(xs,v)):
            if i>=5 and s>=level: stop=x; break
        if t['emb']:
            nemb+=1
            if stop is not None and stop < t['ex']:
                before+=1; leads.append(t['ex']-stop); ahead1 += (t['ex']-stop)>=1
            else: leads.append(0.0 if stop is None else t['ex']-stop)
        else:
            nord+=1; fs += stop is not None
    leads.sort()
    return fs/nord, before/nemb, ahead1/nemb, leads[len(leads)//2]
if __name__ == '__main__':
    trs = load(sys.argv[1])
    for t in trs: t['sig']=signals(t)
    import itertools
    for sig in ['truez','zest','umax','umean','irat','slip']:
        vals=sorted(x for t in trs for x in t['sig'][sig])
        qs=[vals[int(len(vals)*q)] for q in (0.5,0.7,0.8,0.9,0.95,0.97,0.98,0.99)]
        print(sig)
        for lv in qs:
            a=evaluate(trs,sig,lv); b=evaluate(trs,sig,lv,True)
            print('  lvl %.4f  tune fs %.2f before %.2f >=1m %.2f medlead %.2f | held fs %.2f before %.2f >=1m %.2f med %.2f'%((lv,)+a+b))
