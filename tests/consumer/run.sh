#!/usr/bin/env bash
# Installs the build into a temporary prefix and uses it from there as a user would:
#   1. the consumer program built with CMake (find_package(lazytrace), shared and static),
#   2. the same program built with pkg-config,
#   3. the README's C and Python examples, taken out of README.md and run,
# then checks that a program linked to the shared library needs nothing but it and libc.
#   tests/consumer/run.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
python=${LT_PYTHON:-python3}
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
step() { echo "== $*"; }

step "install into a temporary prefix"
cmake --install "$build" --prefix "$prefix/usr" >"$prefix/install.log"
libdir=$(dirname "$(find "$prefix/usr" -name 'liblazytrace.so' | head -1)")
export PKG_CONFIG_PATH="$libdir/pkgconfig"

step "consumer with find_package(lazytrace)"
cmake -S "$src/tests/consumer" -B "$prefix/cmake-build" -DCMAKE_PREFIX_PATH="$prefix/usr" \
  -DCMAKE_BUILD_TYPE=Release >"$prefix/configure.log" || { cat "$prefix/configure.log"; exit 1; }
cmake --build "$prefix/cmake-build" >"$prefix/build.log" || { cat "$prefix/build.log"; exit 1; }
"$prefix/cmake-build/consumer" sphere:2
"$prefix/cmake-build/consumer_static" cornell

step "consumer with pkg-config --cflags --libs lazytrace"
# shellcheck disable=SC2046
cc -std=c11 -Wall -Wextra -Werror "$src/tests/consumer/consumer.c" $(pkg-config --cflags --libs lazytrace) \
  -Wl,-rpath,"$libdir" -o "$prefix/consumer_pc"
"$prefix/consumer_pc" cornell

step "a program linked to liblazytrace.so needs no other library of lazytrace's"
needed=$(readelf -d "$prefix/consumer_pc" | sed -n 's/.*Shared library: \[\(.*\)\]/\1/p' | tr '\n' ' ')
echo "needed: $needed"
for lib in $needed; do
  case $lib in liblazytrace.so.*|libc.so.*|ld-linux*) ;; *) echo "unexpected dependency $lib"; exit 1 ;; esac
done

step "README examples"
examples="$prefix/examples"
mkdir -p "$examples"
# A block preceded by a line '<!-- example: NAME -->' is written to NAME.
awk -v dir="$examples" '
  /^<!-- example: [^ ]+ -->$/ { name = $3; next }
  name != "" && /^```/ { if (open) { open = 0; name = "" } else open = 1; next }
  open { print > (dir "/" name) }' "$src/README.md"
for f in CMakeLists.txt example.c build.sh example.py; do
  [ -s "$examples/$f" ] || { echo "README.md has no example $f"; exit 1; }
done
cmake -S "$examples" -B "$examples/build" -DCMAKE_PREFIX_PATH="$prefix/usr" >"$prefix/example-configure.log" || {
  cat "$prefix/example-configure.log"; exit 1; }
cmake --build "$examples/build" >"$prefix/example-build.log" || { cat "$prefix/example-build.log"; exit 1; }
"$examples/build/example"
(cd "$examples" && LD_LIBRARY_PATH="$libdir" bash build.sh && LD_LIBRARY_PATH="$libdir" ./example)
# The installed Python module finds the installed library by itself.
(cd "$examples" && env -u LAZYTRACE_LIBRARY PYTHONPATH="$prefix/usr/lib/python3/dist-packages" "$python" example.py)
# The MPI example, where Open MPI is installed: built with mpicc against the installed library.
if command -v mpicc >/dev/null && command -v mpirun >/dev/null; then
  [ -s "$examples/example_mpi.c" ] || { echo "README.md has no example example_mpi.c"; exit 1; }
  mpicc -O2 "$examples/example_mpi.c" -I"$prefix/usr/include" -L"$libdir" -llazytrace -lm -o "$examples/example_mpi"
  root=(); [ "$(id -u)" -eq 0 ] && root=(--allow-run-as-root)
  LD_LIBRARY_PATH="$libdir" mpirun "${root[@]}" --oversubscribe -np 2 "$examples/example_mpi"
fi
echo "consumer: all passed"
