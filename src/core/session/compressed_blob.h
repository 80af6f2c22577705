// Blobs stored compressed (zlib): the checkpoint of a session database.
#ifndef RRR_CORE_SESSION_COMPRESSED_BLOB_H_
#define RRR_CORE_SESSION_COMPRESSED_BLOB_H_

#include <string>

namespace rrr {

// `bytes` compressed, led by their size (8 bytes), for Decompress.
std::string Compress(const std::string& bytes);
// The bytes Compress was given. Throws std::runtime_error naming the problem
// if `blob` is not what Compress wrote (cut short, corrupt).
std::string Decompress(const std::string& blob);

}  // namespace rrr

#endif  // RRR_CORE_SESSION_COMPRESSED_BLOB_H_
