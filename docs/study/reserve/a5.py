import sys, math; sys.path.insert(0, __import__('os').path.dirname(__file__))
from load import *
from ev import rmed
trs = load(sys.argv[1]); G=1.62; R=0.15
for t in trs:
    rf=[]
    for r in t['rows']:
        if math.isnan(r['dpmax']): continue
        rf.append((r['dpmax']-t['mass']*G*math.sin(math.radians(r['pitch_deg'])))/(t['mass']*G))
    t['minrf']=min(rf) if rf else 1
    t['u']=rmed([sum(r['T%d'%w] for w in range(6))/(R*sum(r['W%d'%w] for w in range(6))) for r in t['rows']])
    t['z']=rmed([max(r['z%d'%w] for w in range(6)) for r in t['rows']])
def ev(sig, lv, held):
    clear=fs=nm=nms=emb=bef=a1=0; L=[]
    for t in trs:
        if (t['fam'] in HELD)!=held: continue
        stop=None
        for i,(r,v) in enumerate(zip(t['rows'],t[sig])):
            if i>=5 and v>=lv: stop=r['x']; break
        if t['emb']:
            emb+=1; l=(t['ex']-stop) if stop is not None else 0; L.append(l)
            if stop is not None and stop<t['ex']: bef+=1; a1+=l>=1
        elif t['minrf']<0.05: nm+=1; nms+=stop is not None
        else: clear+=1; fs+=stop is not None
    L.sort(); return fs,clear,nms,nm,bef,emb,a1,L[len(L)//2]
for sig,lvs in (('u',(0.38,0.40,0.42,0.44,0.46,0.48)),('z',(0.03,0.035,0.04,0.045,0.05,0.06))):
    for lv in lvs:
        print(sig, lv, 'tuning fs %d/%d nm %d/%d before %d/%d >=1m %d med %.2f'%ev(sig,lv,False), '| held fs %d/%d nm %d/%d before %d/%d >=1m %d med %.2f'%ev(sig,lv,True))
