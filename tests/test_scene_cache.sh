#!/bin/sh
# test_scene_cache.sh: the scene and structure caches (src/scene/scene_cache.h,
# src/render/accel_cache.h) as a user meets them. A warm render is byte for byte the cold one
# (the bunny; Sponza with its textures, path traced; arrays split over buffers); a changed OBJ
# (a new time; new bytes under the old size and time) or .mtl is parsed again; a damaged or
# truncated entry is parsed or built again; the OBJ's warnings are printed again from the cache;
# four runs at once on an empty cache agree; an unwritable cache or a full disk only warns;
# --no-cache writes nothing; a .glb with an embedded texture comes back with it; VKRT_SCENE_CACHE_DIR moves the meshes and structures, or (empty)
# keeps none. Run by meson test with VKRT_BINARY, VKRT_SOURCE_DIR and
# VKRT_SCENES_DIR; the shared scenes' cases are skipped where they are absent.
set -u
vkrt=${VKRT_BINARY:?}
src=${VKRT_SOURCE_DIR:?}
scenes=${VKRT_SCENES_DIR:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$src/tests/lib.sh"
export VKRT_CACHE_DIR="$tmp/cache"
small="--width 24 --height 24 --spp 1"

# render NAME CFG ARGS...: renders CFG to $tmp/NAME.png, its --verbose lines in $tmp/NAME.err.
render() {
    name=$1 cfg=$2
    shift 2
    # shellcheck disable=SC2086 # $small is meant to split into words
    "$vkrt" render "$cfg" $small --verbose -o "$tmp/$name.png" "$@" 2>"$tmp/$name.err"
    check "$name exits 0" test $? -eq 0
}
said() { # said NAME PATTERN: NAME's messages have a line matching PATTERN
    grep -q "$2" "$tmp/$1.err"
}
same() { # same A B: the two renders are the same bytes
    cmp -s "$tmp/$1.png" "$tmp/$2.png"
}

# A made OBJ over 1 MiB (what is stored): a grid of 40000 triangles under two materials of its
# .mtl, with a face of two corners that the loader drops with a warning naming its line.
mkdir -p "$tmp/made"
awk 'BEGIN {
    print "mtllib made.mtl"
    n = 80
    m = 250
    for (j = 0; j <= n; ++j)
        for (i = 0; i <= m; ++i)
            printf "v %.6f %.6f %.6f\n", i / m - 0.5, j / n - 0.5, 0.05 * sin(i * 0.3 + j * 0.2)
    for (j = 0; j < n; ++j) {
        print (j < n / 2 ? "usemtl red" : "usemtl blue")
        for (i = 0; i < m; ++i) {
            a = j * (m + 1) + i + 1
            printf "f %d %d %d\nf %d %d %d\n", a, a + 1, a + m + 2, a, a + m + 2, a + m + 1
        }
    }
    print "f 1 2"
}' >"$tmp/made/made.obj"
printf 'newmtl red\nKd 0.8 0.1 0.1\nnewmtl blue\nKd 0.1 0.1 0.8\nnewmtl bluf\nKd 0.1 0.8 0.1\n' \
    >"$tmp/made/made.mtl"
cat >"$tmp/made/scene.cfg" <<'EOF'
geometry made.obj
light directional 0 0 -1 2 2 2
camera eye 0 0 1.5 look 0 0 0 up 0 1 0 fov 45
EOF
made="$tmp/made/scene.cfg"

render made-cold "$made"
check "a parsed OBJ is stored" said made-cold "^vkrt: scene cache: scene file parsed, model stored"
check "its warning is printed" said made-cold "made.obj:[0-9]*: warning: .*"
render made-warm "$made"
check "the next start reads the mesh" said made-warm "^vkrt: scene cache: model read in"
check "and renders the same bytes" same made-cold made-warm
grep "warning" "$tmp/made-cold.err" >"$tmp/warnings-cold"
grep "warning" "$tmp/made-warm.err" >"$tmp/warnings-warm"
check "and prints the same warnings" cmp -s "$tmp/warnings-cold" "$tmp/warnings-warm"
check "(there are warnings to compare)" test -s "$tmp/warnings-warm"

# A new time on the same bytes: parsed again (the key holds the time).
touch -d "2001-01-01 00:00:00" "$tmp/made/made.obj"
render made-touched "$made"
check "an OBJ with a new time is parsed again" said made-touched "scene file parsed, model stored"
check "and renders the same" same made-cold made-touched
# New bytes under the old size and time: the content hash tells them apart. The blue half turns
# green (the .mtl's bluf), one letter a line.
sed 's/^usemtl blue$/usemtl bluf/' "$tmp/made/made.obj" >"$tmp/edited.obj"
touch -r "$tmp/made/made.obj" "$tmp/edited.obj"
cp -p "$tmp/edited.obj" "$tmp/made/made.obj"
check "(the edit kept the size)" test "$(wc -c <"$tmp/edited.obj")" -eq "$(wc -c <"$tmp/made/made.obj")"
render made-edited "$made"
check "an OBJ rewritten under the same size and time is parsed again" \
    said made-edited "scene file parsed, model stored"
check "and renders the new scene" sh -c "! cmp -s '$tmp/made-cold.png' '$tmp/made-edited.png'"
check "and its entry replaces the old version's" \
    test "$(find "$VKRT_CACHE_DIR" -name '*.mesh' | wc -l)" -eq 1
# A changed .mtl: the entry lists it with its identity.
render made-again "$made"
check "(the edited OBJ is read from the cache)" said made-again "model read in"
sed 's/^Kd 0.1 0.8 0.1$/Kd 0.8 0.8 0.1/' "$tmp/made/made.mtl" >"$tmp/edited.mtl"
cp "$tmp/edited.mtl" "$tmp/made/made.mtl"
render made-mtl "$made"
check "a changed .mtl is noticed" said made-mtl "not used (a file the scene file names changed); scene file parsed"
check "and its colours are rendered" sh -c "! cmp -s '$tmp/made-again.png' '$tmp/made-mtl.png'"

# Damaged and truncated entries: parsed and built again, the same image.
render made-ref "$made" --accel bvh
render made-ref2 "$made" --accel bvh
check "(the BVH comes from the cache)" said made-ref2 "read from the structure cache"
for entry in "$VKRT_CACHE_DIR"/*.mesh "$VKRT_CACHE_DIR"/*.accel; do
    size=$(wc -c <"$entry")
    # Eight bytes in the middle of the arrays, changed.
    printf 'XYZWXYZW' | dd of="$entry" bs=1 seek=$((size / 2)) conv=notrunc 2>/dev/null
done
render made-damaged "$made" --accel bvh
check "a damaged mesh is parsed again" said made-damaged "not used (a damaged entry); scene file parsed"
check "a damaged structure is built again" said made-damaged "^vkrt: BVH: .* built in"
check "and the image is the same" same made-ref made-damaged
for entry in "$VKRT_CACHE_DIR"/*.mesh "$VKRT_CACHE_DIR"/*.accel; do
    size=$(wc -c <"$entry")
    head -c $((size - 100)) "$entry" >"$tmp/short" && cat "$tmp/short" >"$entry"
done
render made-truncated "$made" --accel bvh
check "a truncated mesh is parsed again" said made-truncated "not used (a damaged entry); scene file parsed"
check "a truncated structure is built again" said made-truncated "^vkrt: BVH: .* built in"
check "and the image is the same" same made-ref made-truncated

# Four runs at once on an empty cache: each whole, the same image, no temporary file left.
rm -rf "$VKRT_CACHE_DIR"
for i in 1 2 3 4; do
    "$vkrt" render "$made" $small --accel bvh -o "$tmp/run$i.png" 2>"$tmp/run$i.err" &
done
wait
for i in 1 2 3 4; do
    check "concurrent run $i renders the same" same made-ref run$i
done
check "no temporary file is left" test -z "$(find "$VKRT_CACHE_DIR" -name '*.tmp')"
render made-after "$made" --accel bvh
check "and the next start reads both entries" \
    sh -c "grep -q 'model read in' '$tmp/made-after.err' && grep -q 'read from the structure cache' '$tmp/made-after.err'"

# A cache that cannot be written: a warning, the render as ever.
: >"$tmp/a-file"
VKRT_CACHE_DIR="$tmp/a-file/cache" "$vkrt" render "$made" $small -o "$tmp/unwritable.png" \
    2>"$tmp/unwritable.err"
check "an unwritable cache renders" test $? -eq 0
check "and warns once" test "$(grep -c "^vkrt: warning: .* cache: cannot write $tmp/a-file/cache: Not a directory" "$tmp/unwritable.err")" -eq 1
# A full disk, as a file size limit (EFBIG): the mesh's write fails part way.
rm -rf "$VKRT_CACHE_DIR"
(trap '' XFSZ; ulimit -f 512; "$vkrt" render "$made" $small -o "$tmp/full.png" 2>"$tmp/full.err")
check "a full disk renders" test $? -eq 0
check "and warns" grep -q "^vkrt: warning: scene cache: cannot write .*\.mesh: File too large" "$tmp/full.err"
check "and leaves no part of an entry" test -z "$(find "$VKRT_CACHE_DIR" -name '*.mesh*')"
# --no-cache: nothing read or written.
rm -rf "$VKRT_CACHE_DIR"
render nocache "$made" --no-cache
check "--no-cache writes no mesh" test -z "$(find "$tmp" -name '*.mesh')"
check "--no-cache says nothing of the scene cache" sh -c "! grep -q 'scene cache' '$tmp/nocache.err'"

# VKRT_SCENE_CACHE_DIR: meshes and structures elsewhere, or (empty) not kept, kernels as ever.
rm -rf "$VKRT_CACHE_DIR"
VKRT_SCENE_CACHE_DIR="$tmp/scenes" render elsewhere "$made" --accel bvh
check "VKRT_SCENE_CACHE_DIR holds the mesh and the structure" \
    test "$(find "$tmp/scenes" -name '*.mesh' -o -name '*.accel' | wc -l)" -eq 2
check "and the kernels stay in VKRT_CACHE_DIR" test -n "$(find "$VKRT_CACHE_DIR" -name '*.spv')"
check "and no mesh goes there" test -z "$(find "$VKRT_CACHE_DIR" -name '*.mesh')"
rm -rf "$tmp/scenes"
VKRT_SCENE_CACHE_DIR= render nowhere "$made" --accel bvh
check "VKRT_SCENE_CACHE_DIR= keeps no mesh" test -z "$(find "$tmp" -name '*.mesh')"
check "and reads the kernels" said nowhere "kernels: 0 compiled"

# A glTF over 1 MiB with its texture embedded in the .glb (model.images): stored cold, read
# warm with the image, the same picture; its framed camera and white sky need no scene.cfg.
python3 - "$tmp/made/made.glb" <<'PY'
import json, struct, sys, zlib
n = 300  # an n x n grid of quads: 180000 triangles
pos, uv, idx = bytearray(), bytearray(), bytearray()
for j in range(n + 1):
    for i in range(n + 1):
        pos += struct.pack("<3f", i / n - 0.5, j / n - 0.5, 0.0)
        uv += struct.pack("<2f", i / n, 1.0 - j / n)
for j in range(n):
    for i in range(n):
        a = j * (n + 1) + i
        idx += struct.pack("<6I", a, a + 1, a + n + 2, a, a + n + 2, a + n + 1)
# A 2 x 2 texture: red, green over blue, white (PNG rows top first).
raw = b"\0" + bytes([255, 0, 0, 0, 255, 0]) + b"\0" + bytes([0, 0, 255, 255, 255, 255])
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, 8, 2, 0, 0, 0)) +
       chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
png += b"\0" * (-len(png) % 4)
blob = bytes(pos + uv + idx) + png
views = [(0, len(pos)), (len(pos), len(uv)), (len(pos) + len(uv), len(idx)), (len(pos) + len(uv) + len(idx), len(png))]
doc = {
    "asset": {"version": "2.0"},
    "buffers": [{"byteLength": len(blob)}],
    "bufferViews": [{"buffer": 0, "byteOffset": o, "byteLength": l} for o, l in views],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": (n + 1) ** 2, "type": "VEC3",
         "min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 0]},
        {"bufferView": 1, "componentType": 5126, "count": (n + 1) ** 2, "type": "VEC2"},
        {"bufferView": 2, "componentType": 5125, "count": 6 * n * n, "type": "SCALAR"}],
    "images": [{"bufferView": 3, "mimeType": "image/png"}],
    "samplers": [{"magFilter": 9729}],
    "textures": [{"source": 0, "sampler": 0}],
    "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
    "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}
text = json.dumps(doc).encode()
text += b" " * (-len(text) % 4)
with open(sys.argv[1], "wb") as f:
    f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(blob)))
    f.write(struct.pack("<II", len(text), 0x4E4F534A) + text)
    f.write(struct.pack("<II", len(blob), 0x004E4942) + blob)
PY
render glb-cold "$tmp/made/made.glb"
check "glTF: cold parse stored" said glb-cold "^vkrt: scene cache: scene file parsed, model stored"
render glb-warm "$tmp/made/made.glb"
check "glTF: warm read from the cache" said glb-warm "^vkrt: scene cache: model read in"
check "glTF: warm renders the cold image" same glb-cold glb-warm

# The shared scenes: the bunny, Sponza with its textures, and the bunny's arrays split over
# buffers, each cold then warm (the made scene above took lavapipe's kd-tree).
if [ -z "${VKRT_SKIP_SHARED_SCENES:-}" ] && [ -n "$scenes" ] &&
    [ -f "$scenes/stanford-bunny/stanford-bunny.obj" ] &&
    [ -f "$scenes/dabrovic-sponza/sponza.obj" ]; then
    bunny="$src/scenes/shared/bunny.cfg"
    for accel in bvh; do
        render bunny-$accel-cold "$bunny" --accel $accel
        render bunny-$accel-warm "$bunny" --accel $accel
        check "bunny ($accel): warm from both caches" \
            sh -c "grep -q 'model read in' '$tmp/bunny-$accel-warm.err' && grep -q 'read from the structure cache' '$tmp/bunny-$accel-warm.err'"
        check "bunny ($accel): warm renders the cold image" same bunny-$accel-cold bunny-$accel-warm
    done
    sponza="$src/scenes/shared/sponza-path.cfg"
    render sponza-cold "$sponza" --accel bvh
    render sponza-warm "$sponza" --accel bvh
    check "Sponza: warm from the cache" said sponza-warm "model read in"
    check "Sponza: warm renders the cold image, textures and all" same sponza-cold sponza-warm
    rm -rf "$VKRT_CACHE_DIR"
    VKRT_TEST_MAX_BUFFER_BYTES=400000 render split-cold "$bunny" --accel bvh
    VKRT_TEST_MAX_BUFFER_BYTES=400000 render split-warm "$bunny" --accel bvh
    check "split arrays: as asked" said split-warm "^vkrt: arrays split past 400000 bytes .*: triangles in"
    check "split arrays: warm renders the cold image" same split-cold split-warm
    check "split arrays: and the whole one" same split-cold bunny-bvh-cold
fi
summary
