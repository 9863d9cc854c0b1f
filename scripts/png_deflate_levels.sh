#!/usr/bin/env bash
# The PNG encoder's compression measured alone (the figures of the README's "Output"): renders
# three images to PNG with build/bin/penumbra, takes their Sub-filtered rows back out, and times
# zlib (deflateInit2 with Z_FILTERED, as libpng used it before) against libdeflate (its zlib
# container, as core/png_encoder.cpp uses it) at levels 4 and 6, best of 15 each. Run from the
# repository after the README's build, with ../shared beside it; needs zlib1g-dev.
set -eu
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cat > $tmp/zt.c <<'C'
#include <zlib.h>
#include <stdio.h>
#include <time.h>
static double now(){struct timespec t;clock_gettime(CLOCK_MONOTONIC,&t);return t.tv_sec+t.tv_nsec*1e-9;}
int main(int c,char**v){FILE*f=fopen(v[1],"rb");static unsigned char in[1<<22],out[1<<22];size_t n=fread(in,1,sizeof in,f);
for(int lvl=4;lvl<=6;lvl+=2){double best=1e9;unsigned long sz=0;for(int r=0;r<15;r++){z_stream s={0};deflateInit2(&s,lvl,Z_DEFLATED,15,8,Z_FILTERED);s.next_in=in;s.avail_in=n;s.next_out=out;s.avail_out=sizeof out;double t=now();deflate(&s,Z_FINISH);t=now()-t;sz=s.total_out;deflateEnd(&s);if(t<best)best=t;}printf("zlib %d: %.2f ms %lu bytes\n",lvl,best*1e3,sz);}}
C
cat > $tmp/dt.c <<'C'
#include <libdeflate.h>
#include <stdio.h>
#include <time.h>
static double now(){struct timespec t;clock_gettime(CLOCK_MONOTONIC,&t);return t.tv_sec+t.tv_nsec*1e-9;}
int main(int c,char**v){FILE*f=fopen(v[1],"rb");static unsigned char in[1<<22],out[1<<22];size_t n=fread(in,1,sizeof in,f);
for(int lvl=4;lvl<=6;lvl+=2){double best=1e9;size_t sz=0;for(int r=0;r<15;r++){double t=now();struct libdeflate_compressor*k=libdeflate_alloc_compressor(lvl);sz=libdeflate_zlib_compress(k,in,n,out,sizeof out);libdeflate_free_compressor(k);t=now()-t;if(t<best)best=t;}printf("libdeflate %d: %.2f ms %zu bytes\n",lvl,best*1e3,sz);}}
C
gcc -O2 $tmp/zt.c -o $tmp/zt -lz && gcc -O2 $tmp/dt.c -o $tmp/dt -ldeflate
cd "$(dirname "$0")/.."
build/bin/penumbra ../shared/bench/textbook_fig24_06.json -q -o $tmp/img_fig24.png
build/bin/penumbra assets/cornell/cornell.obj -q -o $tmp/img_cornell.png
build/bin/penumbra ../shared/bench/room.json --spp 4 -q -o $tmp/img_room.png
for img in $tmp/img_fig24.png $tmp/img_cornell.png $tmp/img_room.png; do
  python3 -c "
import struct,zlib,sys
raw=open('$img','rb').read(); i=8; idat=b''
while i<len(raw):
    n=struct.unpack('>I',raw[i:i+4])[0]
    if raw[i+4:i+8]==b'IDAT': idat+=raw[i+8:i+8+n]
    i+=12+n
open('$tmp/filtered.bin','wb').write(zlib.decompress(idat))"
  echo "== $(basename "$img") ($(stat -c %s $tmp/filtered.bin) filtered bytes)"; $tmp/zt $tmp/filtered.bin; $tmp/dt $tmp/filtered.bin
done
