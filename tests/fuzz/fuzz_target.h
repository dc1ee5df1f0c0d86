/* One fuzz target: LLVMFuzzerTestOneInput feeds bytes to one of lazytrace's readers. Built
 * with libFuzzer by scripts/fuzz (clang -fsanitize=fuzzer,address), or with the bounded driver
 * tests/fuzz/driver.c into the test suite, where it runs the seed corpus and a few thousand
 * mutations of it in seconds. A reader must answer every input with a clean status: no crash,
 * no hang, no leak, no read out of bounds. */
#ifndef LT_FUZZ_TARGET_H
#define LT_FUZZ_TARGET_H

#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Writes the bytes to a private temporary file whose name ends in `suffix` (readers pick the
 * format by extension) and returns its path (static storage), or NULL. */
const char *lt_fuzz_file(const uint8_t *data, size_t size, const char *suffix);

#endif
