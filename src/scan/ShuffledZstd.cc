// levelfuse: arrays compressed as their scalars' bytes shuffled and Zstandard.

#include "ShuffledZstd.h"

#include <zstd.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

namespace levelfuse::detail {

namespace {

/// Zstandard's fastest positive level: a depth frame's readings shrink about sixfold in about a millisecond.
constexpr int kLevel = 1;
/// Bytes shuffled at a time (a multiple of every scalar's size), so that a
/// large array is never held twice.
constexpr std::size_t kBlockBytes = std::size_t(1) << 18;

struct FreeCompression {
  void operator()(ZSTD_CCtx* c) const { ZSTD_freeCCtx(c); }
};
struct FreeDecompression {
  void operator()(ZSTD_DCtx* d) const { ZSTD_freeDCtx(d); }
};

ZSTD_CCtx& compressionContext() {
  thread_local std::unique_ptr<ZSTD_CCtx, FreeCompression> context(ZSTD_createCCtx());
  if (!context) throw std::runtime_error("PackedRangeMap: Zstandard could not make a compression context");
  return *context;
}

ZSTD_DCtx& decompressionContext() {
  thread_local std::unique_ptr<ZSTD_DCtx, FreeDecompression> context(ZSTD_createDCtx());
  if (!context) throw std::runtime_error("PackedRangeMap: Zstandard could not make a decompression context");
  return *context;
}

/// Throws if `code` is one of Zstandard's errors; else returns it.
std::size_t checked(std::size_t code, const char* what) {
  if (ZSTD_isError(code)) throw std::runtime_error(std::string("PackedRangeMap: ") + what + ": " + ZSTD_getErrorName(code));
  return code;
}

/// Byte k of scalar i of `in` to out[k * count + i] (count = bytes / S), or
/// back (`gather`).
template <std::size_t S>
void reorder(const unsigned char* in, std::size_t bytes, unsigned char* out, bool gather) {
  const std::size_t count = bytes / S;
  for (std::size_t i = 0; i < count; ++i)
    for (std::size_t k = 0; k < S; ++k) {
      if (gather) out[i * S + k] = in[k * count + i];
      else out[k * count + i] = in[i * S + k];
    }
}

/// reorder for the scalars' size told at run time: the sizes of the arrays
/// packed (1, 2, 4 and 8 bytes) with their loops unrolled.
void reorder(const unsigned char* in, std::size_t bytes, std::size_t scalarSize, unsigned char* out, bool gather) {
  switch (scalarSize) {
    case 1:
      std::copy(in, in + bytes, out);
      return;
    case 2:
      return reorder<2>(in, bytes, out, gather);
    case 4:
      return reorder<4>(in, bytes, out, gather);
    case 8:
      return reorder<8>(in, bytes, out, gather);
    default:
      throw std::invalid_argument("PackedRangeMap: scalars of " + std::to_string(scalarSize) + " bytes");
  }
}

}  // namespace

std::vector<char> shuffleAndCompress(const void* data, std::size_t bytes, std::size_t scalarSize) {
  if (bytes == 0) return {};
  if (scalarSize == 0 || bytes % scalarSize != 0 || kBlockBytes % scalarSize != 0)
    throw std::invalid_argument("PackedRangeMap: an array is not a whole number of its scalars");
  ZSTD_CCtx& context = compressionContext();
  checked(ZSTD_CCtx_reset(&context, ZSTD_reset_session_only), "reset");
  checked(ZSTD_CCtx_setParameter(&context, ZSTD_c_compressionLevel, kLevel), "level");
  checked(ZSTD_CCtx_setPledgedSrcSize(&context, bytes), "size");
  std::vector<char> out;
  out.reserve(ZSTD_compressBound(std::min(bytes, kBlockBytes)));
  std::vector<unsigned char> block(std::min(bytes, kBlockBytes));
  std::vector<char> chunk(ZSTD_CStreamOutSize());
  const unsigned char* in = static_cast<const unsigned char*>(data);
  for (std::size_t done = 0; done < bytes;) {
    const std::size_t n = std::min(kBlockBytes, bytes - done);
    reorder(in + done, n, scalarSize, block.data(), false);
    done += n;
    const ZSTD_EndDirective mode = done == bytes ? ZSTD_e_end : ZSTD_e_continue;
    ZSTD_inBuffer input{block.data(), n, 0};
    for (bool finished = false; !finished;) {
      ZSTD_outBuffer output{chunk.data(), chunk.size(), 0};
      const std::size_t left = checked(ZSTD_compressStream2(&context, &output, &input, mode), "compress");
      out.insert(out.end(), chunk.data(), chunk.data() + output.pos);
      finished = mode == ZSTD_e_end ? left == 0 : input.pos == input.size;
    }
  }
  out.shrink_to_fit();
  return out;
}

void decompressAndUnshuffle(const std::vector<char>& packed, void* out, std::size_t bytes, std::size_t scalarSize) {
  if (bytes == 0 && packed.empty()) return;
  if (scalarSize == 0 || bytes % scalarSize != 0)
    throw std::invalid_argument("PackedRangeMap: an array is not a whole number of its scalars");
  ZSTD_DCtx& context = decompressionContext();
  checked(ZSTD_DCtx_reset(&context, ZSTD_reset_session_only), "reset");
  std::vector<unsigned char> block(std::min(bytes, kBlockBytes));
  unsigned char* to = static_cast<unsigned char*>(out);
  ZSTD_inBuffer input{packed.data(), packed.size(), 0};
  std::size_t done = 0, left = 1;
  while (done < bytes) {
    const std::size_t n = std::min(kBlockBytes, bytes - done);
    ZSTD_outBuffer output{block.data(), n, 0};
    while (output.pos < n) {
      const std::size_t before = input.pos + output.pos;
      left = checked(ZSTD_decompressStream(&context, &output, &input), "decompress");
      if (input.pos + output.pos == before) throw std::runtime_error("PackedRangeMap: a range map restored incomplete");
    }
    reorder(block.data(), n, scalarSize, to + done, true);
    done += n;
  }
  // The frame must end with the last byte: nothing more to restore, nothing left over.
  if (left != 0) {
    ZSTD_outBuffer none{nullptr, 0, 0};
    left = checked(ZSTD_decompressStream(&context, &none, &input), "decompress");
  }
  if (left != 0 || input.pos != input.size) throw std::runtime_error("PackedRangeMap: a range map restored incomplete");
}

}  // namespace levelfuse::detail
