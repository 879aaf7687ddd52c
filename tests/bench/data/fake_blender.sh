#!/bin/sh
# A Blender for the render cache's tests: copied into a folder of its own, it answers
# black 64 x 64 images (cycles_pair_tiny.yaml), or crashes when a file `crash` lies
# beside it. $7 is the exported scene; the answer goes beside it.
d=$(dirname "$7")
if [ -e "$(dirname "$0")/crash" ]; then kill -SEGV $$; fi
head -c 49152 /dev/zero > "$d/colour.f32"; head -c 16384 /dev/zero > "$d/index.i32"
