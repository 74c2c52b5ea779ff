#include "f2c/io/block.h"

#include <bzlib.h>
#include <fmt/format.h>
#include <lz4frame.h>
#include <zstd.h>

#include <algorithm>
#include <limits>
#include <tuple>

#include "f2c/io/image.h"
#include "f2c/util/error.h"

namespace f2c {

std::string CompressionName(EmbeddedImage::Compression compression) {
  switch (compression) {
    case EmbeddedImage::Compression::kNone:
      return "none";
    case EmbeddedImage::Compression::kBz2:
      return "bz2";
    case EmbeddedImage::Compression::kLz4:
      return "lz4";
    case EmbeddedImage::Compression::kZstd:
      return "zstd";
  }
  return "?";
}

namespace {

// Decompress the first `want` bytes (of `size`): all of them are checked only when want ==
// size (the stream must then end exactly there).
std::string DecompressBz2(const std::string& in, uint64_t size, uint64_t want, const std::string& where) {
  std::string out(want, '\0');
  bz_stream s{};
  if (BZ2_bzDecompressInit(&s, 0, 0) != BZ_OK) ThrowInputError(where, "cannot start bz2 decompression");
  s.next_in = const_cast<char*>(in.data());
  s.avail_in = static_cast<unsigned>(in.size());
  s.next_out = out.data();
  s.avail_out = static_cast<unsigned>(out.size());
  int status = BZ_OK;
  while (status == BZ_OK && s.avail_out > 0 && s.avail_in > 0) status = BZ2_bzDecompress(&s);
  // A whole chunk: the stream ends where its size says, not later.
  if (want == size && status == BZ_OK && s.avail_out == 0) {
    char extra;
    s.next_out = &extra;
    s.avail_out = 1;
    status = BZ2_bzDecompress(&s);
    if (s.avail_out == 0) status = BZ_DATA_ERROR;
  }
  const uint64_t got = want - s.avail_out;
  BZ2_bzDecompressEnd(&s);
  const bool ended = status == BZ_STREAM_END || (want < size && status == BZ_OK);
  if (!ended || got != want) {
    ThrowInputError(where, status == BZ_OK || status == BZ_STREAM_END
                               ? fmt::format("damaged bz2 chunk (not {} bytes)", size)
                               : fmt::format("damaged bz2 chunk (bzip2 error {})", status));
  }
  return out;
}

std::string DecompressLz4(const std::string& in, uint64_t size, uint64_t want, const std::string& where) {
  LZ4F_dctx* context = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&context, LZ4F_VERSION))) {
    ThrowInputError(where, "cannot start lz4 decompression");
  }
  std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> guard(context, LZ4F_freeDecompressionContext);
  // One byte of room past a whole chunk, to see that the stream ends there.
  std::string out(want == size ? want + 1 : want, '\0');
  size_t in_pos = 0, out_pos = 0, hint = 1;
  while (hint != 0 && in_pos < in.size() && out_pos < out.size()) {
    size_t in_n = in.size() - in_pos, out_n = out.size() - out_pos;
    hint = LZ4F_decompress(context, out.data() + out_pos, &out_n, in.data() + in_pos, &in_n, nullptr);
    if (LZ4F_isError(hint)) {
      ThrowInputError(where, fmt::format("damaged lz4 chunk ({})", LZ4F_getErrorName(hint)));
    }
    in_pos += in_n;
    out_pos += out_n;
    if (in_n == 0 && out_n == 0) break;
  }
  if (want == size ? hint != 0 || out_pos != size : out_pos < want) {
    ThrowInputError(where, fmt::format("damaged lz4 chunk (not {} bytes)", size));
  }
  out.resize(want);
  return out;
}

std::string DecompressZstd(const std::string& in, uint64_t size, uint64_t want, const std::string& where) {
  std::unique_ptr<ZSTD_DStream, decltype(&ZSTD_freeDStream)> stream(ZSTD_createDStream(), ZSTD_freeDStream);
  if (!stream) ThrowInputError(where, "cannot start zstd decompression");
  ZSTD_initDStream(stream.get());
  std::string out(want == size ? want + 1 : want, '\0');
  ZSTD_inBuffer input{in.data(), in.size(), 0};
  ZSTD_outBuffer output{out.data(), out.size(), 0};
  size_t hint = 1;
  while (hint != 0 && output.pos < output.size) {
    const size_t before_in = input.pos, before_out = output.pos;
    hint = ZSTD_decompressStream(stream.get(), &output, &input);
    if (ZSTD_isError(hint)) ThrowInputError(where, fmt::format("damaged zstd chunk ({})", ZSTD_getErrorName(hint)));
    if (input.pos == before_in && output.pos == before_out) break;
  }
  if (want == size ? hint != 0 || output.pos != size : output.pos < want) {
    ThrowInputError(where, fmt::format("damaged zstd chunk (not {} bytes)", size));
  }
  out.resize(want);
  return out;
}

std::string DecompressPrefix(const std::string& compressed, EmbeddedImage::Compression compression,
                             uint64_t uncompressed_size, uint64_t want, const std::string& where) {
  // A bag's chunks are a few megabytes (rosbag's default 768 KiB, larger only to hold one
  // large message): a size past 1 GiB is damage, not data to allocate for.
  if (uncompressed_size > (uint64_t{1} << 30) || compressed.size() > (uint64_t{1} << 30)) {
    ThrowInputError(
        where, fmt::format("chunk of {} bytes ({} uncompressed; at most 1 GiB)", compressed.size(), uncompressed_size));
  }
  want = std::min(want, uncompressed_size);
  switch (compression) {
    case EmbeddedImage::Compression::kNone:
      if (compressed.size() != uncompressed_size) {
        ThrowInputError(where, fmt::format("chunk of {} bytes says {}", compressed.size(), uncompressed_size));
      }
      return compressed.substr(0, want);
    case EmbeddedImage::Compression::kBz2:
      return DecompressBz2(compressed, uncompressed_size, want, where);
    case EmbeddedImage::Compression::kLz4:
      return DecompressLz4(compressed, uncompressed_size, want, where);
    case EmbeddedImage::Compression::kZstd:
      return DecompressZstd(compressed, uncompressed_size, want, where);
  }
  ThrowInputError(where, "unknown compression");
}

}  // namespace

std::string Decompress(const std::string& compressed, EmbeddedImage::Compression compression,
                       uint64_t uncompressed_size, const std::string& where) {
  return DecompressPrefix(compressed, compression, uncompressed_size, uncompressed_size, where);
}

std::shared_ptr<const std::string> ReadBlockPrefix(const std::filesystem::path& path, const EmbeddedImage::Block& block,
                                                   uint64_t n) {
  n = std::min(n, block.uncompressed_size);
  thread_local std::tuple<std::string, uint64_t, uint64_t> key;
  thread_local std::shared_ptr<const std::string> bytes;
  auto wanted = std::make_tuple(path.string(), block.offset, block.size);
  if (bytes && key == wanted && bytes->size() >= n) return bytes;
  const std::string where =
      fmt::format("{} ({} chunk at byte {})", path.string(), CompressionName(block.compression), block.offset);
  // The compressed bytes a prefix needs are not known in advance; the whole chunk is read (a
  // few megabytes at most), only the decompression stops early.
  bytes = std::make_shared<const std::string>(DecompressPrefix(ReadFileRange(path, block.offset, block.size),
                                                               block.compression, block.uncompressed_size, n, where));
  key = std::move(wanted);
  return bytes;
}

std::shared_ptr<const std::string> ReadBlock(const std::filesystem::path& path, const EmbeddedImage::Block& block) {
  return ReadBlockPrefix(path, block, block.uncompressed_size);
}

}  // namespace f2c
