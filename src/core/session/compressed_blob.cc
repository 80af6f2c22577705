#include "compressed_blob.h"

#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace rrr {

std::string Compress(const std::string& bytes) {
  const std::uint64_t size = bytes.size();
  uLongf room = compressBound(static_cast<uLong>(bytes.size()));
  std::string blob(sizeof(size) + room, '\0');
  std::memcpy(blob.data(), &size, sizeof(size));
  // Level 1: most of the gain of the default level at half its time.
  if (compress2(reinterpret_cast<Bytef*>(blob.data() + sizeof(size)), &room,
                reinterpret_cast<const Bytef*>(bytes.data()),
                static_cast<uLong>(bytes.size()), 1) != Z_OK) {
    throw std::runtime_error("zlib could not compress the blob");
  }
  blob.resize(sizeof(size) + room);
  return blob;
}

std::string Decompress(const std::string& blob) {
  std::uint64_t size = 0;
  if (blob.size() < sizeof(size)) {
    throw std::runtime_error("the compressed blob has no size");
  }
  std::memcpy(&size, blob.data(), sizeof(size));
  // zlib's best ratio is about 1032:1.
  if (size > 1100 * static_cast<std::uint64_t>(blob.size())) {
    throw std::runtime_error("the compressed blob claims " +
                             std::to_string(size) + " bytes from " +
                             std::to_string(blob.size()));
  }
  std::string bytes(size, '\0');
  uLongf out = static_cast<uLongf>(size);
  const int code =
      uncompress(reinterpret_cast<Bytef*>(bytes.data()), &out,
                 reinterpret_cast<const Bytef*>(blob.data() + sizeof(size)),
                 static_cast<uLong>(blob.size() - sizeof(size)));
  if (code != Z_OK || out != size) {
    throw std::runtime_error(
        "the compressed blob is corrupt (zlib: " +
        std::string(code == Z_OK ? "short" : zError(code)) + ")");
  }
  return bytes;
}

}  // namespace rrr
