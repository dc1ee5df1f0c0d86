#!/usr/bin/env bash
# Real model files through the loaders: every file of Debian's assimp-testmodels collection
# (a few hundred models in some 40 formats, broken ones on purpose among them) is loaded and
# written back as OBJ by `lazytrace scene`. Each must load, or fail with a clear message and
# exit status 1: no crash, no hang (30 s each), nothing else.
#   tests/real_models.sh path/to/lazytrace [MODELS_DIR]
set -uo pipefail
lt=$1
dir=${2:-/usr/share/assimp/models}
if [ ! -d "$dir" ]; then
  echo "real_models: $dir not found (Debian package assimp-testmodels); skipped"
  exit 0
fi
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
loaded=0 refused=0 bad=0
while IFS= read -r -d '' f; do
  case "${f,,}" in *.png | *.jpg | *.jpeg | *.tga | *.bmp | *.dds | *.txt | *.md | *.mtl | *.glsl | *.bin | *.xml | *.pcx | *.ktx2) continue ;; esac
  timeout 30 "$lt" scene "$f" -o "$T/out.obj" >"$T/log" 2>&1
  rc=$?
  if [ $rc -eq 0 ]; then
    loaded=$((loaded + 1))
  elif [ $rc -eq 1 ] && grep -q "^lazytrace: " "$T/log"; then
    refused=$((refused + 1))
  else
    bad=$((bad + 1))
    echo "real_models: $f: exit status $rc (124: hang, >128: crash)"
    tail -3 "$T/log"
  fi
done < <(find "$dir" -type f -print0 | sort -z)
echo "real_models: $((loaded + refused + bad)) files: $loaded loaded, $refused refused with a message, $bad crashed or hung"
[ $bad -eq 0 ]
