import sys, math; sys.path.insert(0, __import__('os').path.dirname(__file__))
from load import *
trs = load(sys.argv[1])
G=1.62
for t in trs:
    xs=[]; rf=[]
    for r in t['rows']:
        if math.isnan(r['dpmax']): continue
        need = t['mass']*G*math.sin(math.radians(r['pitch_deg']))
        xs.append(r['x']); rf.append((r['dpmax']-need)/(t['mass']*G))
    t['rx']=xs; t['rf']=rf
def ev(trs, level, held):
    fs=nord=nemb=before=a1=0; leads=[]
    for t in trs:
        if (t['fam'] in HELD)!=held: continue
        stop=None
        for x,v in zip(t['rx'],t['rf']):
            if v<level: stop=x; break
        if t['emb']:
            nemb+=1; L = (t['ex']-stop) if stop is not None else 0
            if stop is not None and stop<t['ex']: before+=1; a1+= L>=1
            leads.append(L)
        else: nord+=1; fs+= stop is not None
    leads.sort(); return nord, fs, nemb, before, a1, leads[len(leads)//2] if leads else 0
for lv in (0.0,0.01,0.02,0.03,0.05,0.07,0.1,0.15):
    print('reserve<%.2f'%lv, 'tune ord %d fs %d emb %d before %d >=1m %d medlead %.2f'%ev(trs,lv,False), '| held ord %d fs %d emb %d before %d >=1m %d med %.2f'%ev(trs,lv,True))
# min reserve of ordinary drives
print(sorted(round(min(t['rf']),3) for t in trs if not t['emb'] and t['rf'])[:15])
print('trend-extrapolated ideal reserve: stop when rf(x) + D*slope_1m < 0')
def ev2(trs, D, lv, held):
    fs=nord=nemb=before=a1=0; leads=[]
    for t in trs:
        if (t['fam'] in HELD)!=held: continue
        stop=None
        xs, rf = t['rx'], t['rf']
        for i in range(len(xs)):
            j=i
            while j>0 and xs[i]-xs[j] < 1.0: j-=1
            sl = (rf[i]-rf[j])/(xs[i]-xs[j]) if xs[i]>xs[j] else 0
            if rf[i] + D*min(sl,0) < lv: stop=xs[i]; break
        if t['emb']:
            nemb+=1; L=(t['ex']-stop) if stop is not None else 0
            if stop is not None and stop<t['ex']: before+=1; a1+=L>=1
            leads.append(L)
        else: nord+=1; fs+= stop is not None
    leads.sort(); return nord, fs, nemb, before, a1, leads[len(leads)//2]
for D in (1,2,3):
  for lv in (0.0, 0.02, 0.05):
    print('D %d lv %.2f'%(D,lv), 'tune ord %d fs %d emb %d before %d >=1m %d med %.2f'%ev2(trs,D,lv,False), '| held ord %d fs %d emb %d before %d >=1m %d med %.2f'%ev2(trs,D,lv,True))
