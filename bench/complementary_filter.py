#!/usr/bin/python3
# Prototype (not kept): keeps the high-pass part of each frame's correction from one TUM
# trajectory (REF) to another (ICP): ICP = REF exp(d_k), d_k minus its mean over +-HALF frames.
#   complementary_filter.py REF.txt ICP.txt OUT.txt HALF
import numpy as np, sys
from scipy.spatial.transform import Rotation as R
def load(f):
    ts=[];p=[];q=[]
    for l in open(f):
        if l.startswith('#') or not l.strip(): continue
        v=list(map(float,l.split())); ts.append(v[0]); p.append(v[1:4]); q.append(v[4:8])
    return np.array(ts),np.array(p),R.from_quat(q)
ref,icp,out,half=sys.argv[1],sys.argv[2],sys.argv[3],int(sys.argv[4])
t,pr,rr=load(ref); t2,pi,ri=load(icp)
assert np.allclose(t,t2)
# right perturbation in camera frame: icp = ref * exp(d)
dr=(rr.inv()*ri).as_rotvec()
dt=rr.inv().apply(pi-pr)
d=np.hstack([dr,dt])
n=len(d); sm=np.zeros_like(d)
for k in range(n):
    a=max(0,k-half); b=min(n,k+half+1); sm[k]=d[a:b].mean(0)
hp=d-sm
rn=rr*R.from_rotvec(hp[:,:3]); pn=pr+rr.apply(hp[:,3:])
with open(out,'w') as f:
    for k in range(n):
        qq=rn[k].as_quat(); f.write(f"{t[k]:.6f} {pn[k][0]:.6f} {pn[k][1]:.6f} {pn[k][2]:.6f} {qq[0]:.9f} {qq[1]:.9f} {qq[2]:.9f} {qq[3]:.9f}\n")
