// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer target for the input reader: any text must either read or be rejected with an
// InputError; any other exception, crash, leak or undefined behaviour is a finding.
//   scripts/fuzz 600      (builds with clang and runs for 600 s on tests/fuzz/corpus)

#include <sparsempm/errors.hpp>
#include <sparsempm/input.hpp>

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)smpm::read_input(text, "fuzz.toml");
  } catch (const smpm::InputError&) {
  }
  return 0;
}
