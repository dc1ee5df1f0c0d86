# What every benchmark result records about where it came from; sourced by benchmarks/*.sh.

# The machine: CPU model, cores, memory and operating system, on one line.
lt_machine() {
  echo "$(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores, $(free -g | awk '/Mem:/ {print $2}') GiB; $(grep PRETTY /etc/os-release | cut -d= -f2 | tr -d '"')"
}

# The commit, marked when the code (anything outside docs/) differs from it.
lt_commit() {
  echo "$(git rev-parse --short HEAD)$(git diff --quiet HEAD -- . ':!docs' || echo ' (with uncommitted changes)')"
}
