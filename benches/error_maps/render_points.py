# Renders a legacy-VTK point set with the scalar error_percent (a dense sample of the target,
# coloured by its distance to the wrap) to a PNG: orthographic, z-buffered 2×2 splats,
# 0 % blue → 0.5·max white → max red. Usage: render_points.py IN.vtk OUT.png MAX_PERCENT [BOX [VIEW]]
# BOX = "x0,x1,y0,y1,z0,z1": only the points inside it (target units), scaled to fill the image;
# VIEW = "front": looking along +y (a face at −y), instead of the default oblique view.
# SPLAT (environment, default 2): splat size in pixels, larger for a wrap's sparser vertices.
import os, sys, math, struct, zlib
s=open(sys.argv[1]).read().split()
i=s.index('POINTS'); n=int(s[i+1]); v=list(map(float,s[i+3:i+3+3*n]))
i=s.index('error_percent'); k=i+3
while s[k] in ('LOOKUP_TABLE','default'): k+=1
err=list(map(float,s[k:k+n])); vmax=float(sys.argv[3])
if len(sys.argv)>4:
    b=list(map(float,sys.argv[4].split(',')))
    keep=[j for j in range(n) if all(b[2*a]<=v[3*j+a]<=b[2*a+1] for a in range(3))]
    v=[c for j in keep for c in v[3*j:3*j+3]]; err=[err[j] for j in keep]; n=len(keep)
def colour(t):
    t=max(0.0,min(1.0,t)); stops=[(0,(40,60,200)),(0.5,(240,240,240)),(1,(210,30,30))]
    for (a,ca),(b,cb) in zip(stops,stops[1:]):
        if t<=b:
            u=(t-a)/(b-a); return [int(ca[j]+(cb[j]-ca[j])*u) for j in range(3)]
SPLAT=int(os.environ.get('SPLAT','2'))
W=H=480; ay,ax=math.radians(35),math.radians(-30)
if len(sys.argv)>5 and sys.argv[5]=='front': ay,ax=0.0,math.radians(-90)
R=[]
for j in range(n):
    x,y,z=v[3*j:3*j+3]; x,z=x*math.cos(ay)+z*math.sin(ay),-x*math.sin(ay)+z*math.cos(ay)
    y,z=y*math.cos(ax)-z*math.sin(ax),y*math.sin(ax)+z*math.cos(ax); R.append((x,y,z))
xs=[r[0] for r in R]; ys=[r[1] for r in R]
cx,cy=(min(xs)+max(xs))/2,(min(ys)+max(ys))/2; sc=0.9*W/max(max(xs)-min(xs),max(ys)-min(ys))
zb=[[-1e30]*W for _ in range(H)]; img=[[(255,255,255)]*W for _ in range(H)]
for j,(x,y,z) in enumerate(R):
    px,py=int((x-cx)*sc+W/2),int((cy-y)*sc+H/2)
    for dy in range(SPLAT):
        for dx in range(SPLAT):
            X,Y=px+dx,py+dy
            if 0<=X<W and 0<=Y<H and z>zb[Y][X]:
                zb[Y][X]=z; img[Y][X]=tuple(colour(err[j]/vmax))
# colour bar
for y in range(H-24,H-10):
    for x in range(20,220): img[y][x]=tuple(colour((x-20)/200))
raw=b''.join(b'\x00'+bytes([c for px in row for c in px]) for row in img)
def chunk(k,d): return struct.pack('>I',len(d))+k+d+struct.pack('>I',zlib.crc32(k+d)&0xffffffff)
open(sys.argv[2],'wb').write(b'\x89PNG\r\n\x1a\n'+chunk(b'IHDR',struct.pack('>IIBBBBB',W,H,8,2,0,0,0))+chunk(b'IDAT',zlib.compress(raw,9))+chunk(b'IEND',b''))
print(sys.argv[2], 'max', max(err), 'mean', sum(err)/n)
