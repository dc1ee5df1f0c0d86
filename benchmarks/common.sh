# Sourced by benchmarks/*.sh from the repository root: what every benchmark needs first, and
# what its results record about where they came from.

# Installs what is missing and builds (Release); results go to $R.
R=docs/results
lt_bench_prepare() {
  scripts/setup
  scripts/build
  mkdir -p "$R"
}

# The machine: CPU model, cores, memory and operating system, on one line.
lt_machine() {
  echo "$(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores, $(lt_simd), $(free -g | awk '/Mem:/ {print $2}') GiB; $(grep PRETTY /etc/os-release | cut -d= -f2 | tr -d '"')"
}

# The widest vector instructions the CPU offers (Embree picks its code path by them; ours is AVX2).
lt_simd() {
  if grep -qw avx512f /proc/cpuinfo; then echo "AVX-512"; elif grep -qw avx2 /proc/cpuinfo; then echo "AVX2"; else echo "no AVX2"; fi
}

# The commit, marked when the code (anything outside docs/) differs from it.
lt_commit() {
  echo "$(git rev-parse --short HEAD)$(git diff --quiet HEAD -- . ':!docs' || echo ' (with uncommitted changes)')"
}

# The OpenCL device the runs see (the first one clinfo lists).
lt_opencl_device() { clinfo -l 2>/dev/null | sed -n 's/.*Device #0: //p' | head -1; }

# The lines a results file starts with: the command given, commit, machine, OpenCL device, date.
lt_results_header() {
  echo "- command: \`$1\`"
  echo "- commit: $(lt_commit)"
  echo "- machine: $(lt_machine)"
  echo "- OpenCL: $(lt_opencl_device)"
  echo "- date: $(date -u +%Y-%m-%d)"
}
