// Test-side LZF compressor (greedy, 3-byte hash), written from the format description independently of
// the reader's decompressor, to make binary_compressed PCD fixtures with back references.
#pragma once
#include <string>
#include <string_view>

namespace hg_test {
std::string lzf_compress(std::string_view in);
}
