#pragma once
// The uncompressed bytes of a compressed block of a recording (a ROS bag's bz2 or lz4
// chunk), for the images embedded in it (EmbeddedImage::block).

#include <filesystem>
#include <memory>
#include <string>

#include "f2c/io/sequence.h"

namespace f2c {

// The block's bytes, decompressed; InputError naming `path` and the block when they lie past
// the file's end, do not decompress, or decompress to another size than the block says. The
// last block each thread asked for is kept: a chunk holds many messages, read one after another.
std::shared_ptr<const std::string> ReadBlock(const std::filesystem::path& path, const EmbeddedImage::Block& block);
// The block's first `n` uncompressed bytes, or more (decompression stops there: a message's
// header at the start of a chunk of large images costs little). Checked as far as read.
std::shared_ptr<const std::string> ReadBlockPrefix(const std::filesystem::path& path, const EmbeddedImage::Block& block,
                                                   uint64_t n);

// `compressed` (bz2 or an LZ4 frame, as roslz4 writes them) decompressed to exactly
// `uncompressed_size` bytes; InputError naming `where` otherwise.
std::string Decompress(const std::string& compressed, EmbeddedImage::Compression compression,
                       uint64_t uncompressed_size, const std::string& where);

std::string CompressionName(EmbeddedImage::Compression compression);

// `size` bytes at `offset` of the message blob in row `row` of a ROS 2 .db3 file's messages
// table (ros2bag.cc); InputError naming the file when the row or the bytes are not there.
std::string ReadSqliteBlob(const std::filesystem::path& path, int64_t row, uint64_t offset, uint64_t size);

}  // namespace f2c
