#!/usr/bin/env python3
"""Light under and beside the Cornell box's blocks, from baked PLYs of data/box/box.obj (tools/box-contact.sh).

For each PLY: the floor's vertices (y = 0, facing up), their mean irradiance H [W/m^2]; the vertices more than
3 mm inside a block's footprint (published corners, ../shared/reference/cornell-box.md), whose H is 0 in truth; and
those 3-30 mm outside a footprint, which the blocks do not shade much but a kernel that sees the footprint darkens.
"""
import struct, sys, math
def read(path):
    data=open(path,'rb').read()
    end=data.index(b'end_header\n')+len(b'end_header\n'); header=data[:end].decode(); body=data[end:]
    props=[l.split()[-1] for l in header.splitlines() if l.startswith('property') and 'list' not in l]
    types=[l.split()[1] for l in header.splitlines() if l.startswith('property') and 'list' not in l]
    n=int([l for l in header.splitlines() if l.startswith('element vertex')][0].split()[-1])
    fmt='<'+''.join({'float':'f','uchar':'B'}[t] for t in types); size=struct.calcsize(fmt)
    return [dict(zip(props,struct.unpack_from(fmt,body,i*size))) for i in range(n)]
quads=[[(0.13,0.065),(0.29,0.114),(0.24,0.272),(0.082,0.225)],[(0.265,0.296),(0.423,0.247),(0.472,0.406),(0.314,0.456)]]
def inside(q,x,z,margin=0):
    # inside when the signed distance to every edge has one sign, beyond the margin [m]
    s=[]
    for i in range(4):
        a=q[i]; b=q[(i+1)%4]; ex=b[0]-a[0]; ez=b[1]-a[1]; L=math.hypot(ex,ez)
        s.append(((x-a[0])*ez-(z-a[1])*ex)/L)
    return all(v>margin for v in s) or all(v<-margin for v in s)
def dist_out(q,x,z):
    s=[]
    for i in range(4):
        a=q[i]; b=q[(i+1)%4]; ex=b[0]-a[0]; ez=b[1]-a[1]; L=math.hypot(ex,ez)
        s.append(((x-a[0])*ez-(z-a[1])*ex)/L)
    sign = 1 if sum(s)>0 else -1
    return -min(v*sign for v in s)  # >0 outside
def main():
  for path in sys.argv[1:]:
      vs=[v for v in read(path) if abs(v['y'])<1e-5 and v['ny']>0.99]
      mean=sum(v['irradiance_g'] for v in vs)/len(vs)
      under=[v['irradiance_g'] for v in vs if any(inside(q,v['x'],v['z'],0.003) for q in quads)]
      beside=[v['irradiance_g'] for v in vs if any(0.003<dist_out(q,v['x'],v['z'])<0.03 for q in quads) and not any(inside(q,v['x'],v['z']) for q in quads)]
      print("%s floor vertices %d mean H %.4f | under blocks %d: mean %.4f (%.2f%% of floor mean), max %.4f | beside (3-30 mm) %d: mean %.4f"%(path,len(vs),mean,len(under),sum(under)/max(1,len(under)),100*sum(under)/max(1,len(under))/mean,max(under or [0]),len(beside),sum(beside)/max(1,len(beside))))


if __name__ == "__main__":
  main()
