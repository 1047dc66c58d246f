#!/bin/sh
# spirv_compare.sh: run in a folder holding c_base/ and c_new/, the kernel caches (VKRT_CACHE_DIR) of
# one render of the same scene by two builds; disassembles each cached SPIR-V (header and hash cut
# off) without names, lines and ids, for diff.
# For each cached SPIR-V: strip the 32-byte header and the 8-byte trailing hash, name it by the
# kernel file named in OpSource/OpString, optimize (inline, DCE), and print an opcode histogram hash.
for d in c_base c_new; do
  mkdir -p $d.out
  for f in $d/*.spv; do
    size=$(stat -c %s $f)
    tail -c +33 $f | head -c $((size - 32 - 8)) > ./x.spv
    name=$(spirv-dis ./x.spv 2>/dev/null | grep -m1 -o 'OpString "[^"]*\.comp"' | sed 's/.*"\(.*\)"/\1/')
    [ -z "$name" ] && name=$(basename $f)
    false || cp ./x.spv ./y.spv
    spirv-dis --raw-id ./y.spv | grep -v "OpName\|OpLine\|OpString\|OpSource\|OpModuleProcessed\|OpMemberName\|OpNoLine" | sed 's/%[0-9]*/%/g' > $d.out/$(basename $name).dis
    echo "$d $(basename $name) $(wc -l < $d.out/$(basename $name).dis) $(md5sum < $d.out/$(basename $name).dis | cut -c1-8)"
  done
done
