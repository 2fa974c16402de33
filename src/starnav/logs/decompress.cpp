#include "starnav/logs/decompress.hpp"

#include <bzlib.h>
#include <lz4frame.h>
#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>

#include "starnav/core/error.hpp"

namespace starnav {

namespace {

Error block_error(const std::string& what, const std::string& path, std::size_t offset, const std::string& field) {
  return Error(what + " (compressed block at byte " + std::to_string(offset) + ")", path, 0, field);
}

void check_size(std::size_t size, const std::string& path, std::size_t offset, const std::string& field) {
  if (size > kMaxDecompressedBytes)
    throw block_error("claims " + std::to_string(size) + " bytes decompressed, more than the limit of " +
                          std::to_string(kMaxDecompressedBytes),
                      path, offset, field);
}

}  // namespace

bool is_gzip(std::string_view b) {
  return b.size() >= 2 && static_cast<unsigned char>(b[0]) == 0x1f && static_cast<unsigned char>(b[1]) == 0x8b;
}

std::string gunzip(std::string_view bytes, const std::string& path, std::size_t max_bytes) {
  // The trailer's ISIZE is the last member's length modulo 2^32, so a true length is never below
  // it: a trailer above the limit is refused before anything is inflated.
  if (bytes.size() >= 18) {
    std::uint32_t isize = 0;
    for (int i = 0; i < 4; ++i) isize |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[bytes.size() - 4 + i])) << (8 * i);
    if (isize > max_bytes)
      throw Error("says it decompresses to " + std::to_string(isize) + " bytes, more than the " + std::to_string(max_bytes) + " read at most",
                  path, 0, "gzip");
  }
  z_stream z{};
  // 15 + 16: gzip only (with its header and checksum).
  if (inflateInit2(&z, 15 + 16) != Z_OK) throw Error("cannot start the gzip decoder", path, 0, "gzip");
  std::unique_ptr<z_stream, int (*)(z_stream*)> guard(&z, inflateEnd);
  std::string out;
  char buffer[1 << 16];
  std::size_t consumed = 0;
  // Appends what one inflate call produced, refusing it before it passes the limit; the buffer
  // grows by doubling but never beyond the limit, so refusing costs at most the limit.
  const auto append = [&](std::size_t n) {
    if (n > max_bytes - out.size())
      throw Error("decompresses to more than " + std::to_string(max_bytes) + " bytes, the most read", path, 0, "gzip");
    if (out.size() + n > out.capacity()) out.reserve(std::min(max_bytes, std::max(2 * out.capacity(), out.size() + n)));
    out.append(buffer, n);
  };
  while (consumed < bytes.size()) {
    const std::size_t chunk = std::min<std::size_t>(bytes.size() - consumed, std::numeric_limits<uInt>::max());
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data() + consumed));
    z.avail_in = static_cast<uInt>(chunk);
    int rc = Z_OK;
    do {
      z.next_out = reinterpret_cast<Bytef*>(buffer);
      z.avail_out = sizeof buffer;
      rc = inflate(&z, Z_NO_FLUSH);
      if (rc != Z_OK && rc != Z_STREAM_END && rc != Z_BUF_ERROR)
        throw Error(std::string("corrupt gzip data: ") + (z.msg ? z.msg : "inflate failed") + " at byte " +
                        std::to_string(consumed + (chunk - z.avail_in)),
                    path, 0, "gzip");
      append(sizeof buffer - z.avail_out);
    } while (z.avail_out == 0 && rc != Z_STREAM_END);
    consumed += chunk - z.avail_in;
    if (rc == Z_STREAM_END) {
      // A further member (gzip files may be concatenated) or trailing bytes.
      if (consumed < bytes.size() && is_gzip(bytes.substr(consumed))) {
        inflateReset(&z);
        continue;
      }
      if (consumed < bytes.size()) throw Error("trailing bytes after the gzip data", path, 0, "gzip");
      return out;
    }
    if (z.avail_in == 0 && rc == Z_BUF_ERROR) break;
  }
  throw Error("truncated gzip data", path, 0, "gzip");
}

std::string bunzip2(std::string_view bytes, std::size_t size, const std::string& path, std::size_t offset) {
  check_size(size, path, offset, "bz2");
  if (bytes.size() > std::numeric_limits<unsigned>::max() || size > std::numeric_limits<unsigned>::max())
    throw block_error("bzip2 block too large", path, offset, "bz2");
  // One more byte of room tells a stream longer than announced from an exact one.
  std::string room(size + 1, '\0');
  unsigned out_len = static_cast<unsigned>(room.size());
  const int rc = BZ2_bzBuffToBuffDecompress(room.data(), &out_len, const_cast<char*>(bytes.data()),
                                            static_cast<unsigned>(bytes.size()), 0, 0);
  if (rc == BZ_OUTBUFF_FULL || (rc == BZ_OK && out_len != size))
    throw block_error("bzip2 data does not decompress to the announced " + std::to_string(size) + " bytes", path,
                      offset, "bz2");
  if (rc != BZ_OK) throw block_error("corrupt bzip2 data (libbz2 error " + std::to_string(rc) + ")", path, offset, "bz2");
  room.resize(size);
  return room;
}

std::string lz4_frame_decompress(std::string_view bytes, std::size_t size, const std::string& path, std::size_t offset) {
  check_size(size, path, offset, "lz4");
  LZ4F_dctx* ctx = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION)))
    throw block_error("cannot start the LZ4 decoder", path, offset, "lz4");
  std::unique_ptr<LZ4F_dctx, LZ4F_errorCode_t (*)(LZ4F_dctx*)> guard(ctx, LZ4F_freeDecompressionContext);
  std::string out(size, '\0');
  std::size_t produced = 0, consumed = 0;
  while (true) {
    std::size_t dst = out.size() - produced;
    std::size_t src = bytes.size() - consumed;
    char spare[1];
    // A full output buffer gets a one-byte scratch so that data beyond `size` is noticed.
    char* dst_ptr = dst > 0 ? out.data() + produced : spare;
    if (dst == 0) dst = sizeof spare;
    const std::size_t hint = LZ4F_decompress(ctx, dst_ptr, &dst, bytes.data() + consumed, &src, nullptr);
    if (LZ4F_isError(hint))
      throw block_error(std::string("corrupt LZ4 data: ") + LZ4F_getErrorName(hint), path, offset, "lz4");
    if (dst_ptr == spare && dst > 0)
      throw block_error("LZ4 data longer than the announced " + std::to_string(size) + " bytes", path, offset, "lz4");
    produced += dst_ptr == spare ? 0 : dst;
    consumed += src;
    if (hint == 0) break;  // the frame is complete
    if (src == 0 && dst == 0) throw block_error("truncated LZ4 frame", path, offset, "lz4");
    if (consumed >= bytes.size() && hint != 0) throw block_error("truncated LZ4 frame", path, offset, "lz4");
  }
  if (produced != size)
    throw block_error("LZ4 data decompresses to " + std::to_string(produced) + " bytes, not the announced " +
                          std::to_string(size),
                      path, offset, "lz4");
  return out;
}

}  // namespace starnav
