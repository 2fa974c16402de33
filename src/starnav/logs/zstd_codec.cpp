#include "starnav/logs/zstd_codec.hpp"

#include <zstd.h>
#include <zstd_errors.h>

#include <memory>

#include "starnav/core/error.hpp"
#include "starnav/logs/decompress.hpp"

namespace starnav {

namespace {

Error zstd_error(const std::string& what, const std::string& path, std::size_t offset) {
  return Error(what + " (compressed block at byte " + std::to_string(offset) + ")", path, 0, "zstd");
}

// One decompression context per thread: creating one costs more than a small chunk's decoding.
ZSTD_DCtx* context() {
  thread_local std::unique_ptr<ZSTD_DCtx, std::size_t (*)(ZSTD_DCtx*)> ctx(ZSTD_createDCtx(), ZSTD_freeDCtx);
  return ctx.get();
}

}  // namespace

bool is_zstd(std::string_view b) {
  return b.size() >= 4 && static_cast<unsigned char>(b[0]) == 0x28 && static_cast<unsigned char>(b[1]) == 0xb5 &&
         static_cast<unsigned char>(b[2]) == 0x2f && static_cast<unsigned char>(b[3]) == 0xfd;
}

std::string zstd_decompress(std::string_view bytes, std::size_t size, const std::string& path, std::size_t offset) {
  if (size > kMaxDecompressedBytes)
    throw zstd_error("claims " + std::to_string(size) + " bytes decompressed, more than the limit of " +
                          std::to_string(kMaxDecompressedBytes),
                      path, offset);
  ZSTD_DCtx* ctx = context();
  if (!ctx) throw zstd_error("cannot start the zstd decoder", path, offset);
  std::string out(size, '\0');
  // Frame by frame, so that a frame claiming more than the space left fails before it is decoded.
  std::size_t in = 0, produced = 0;
  while (in < bytes.size()) {
    const std::size_t frame = ZSTD_findFrameCompressedSize(bytes.data() + in, bytes.size() - in);
    if (ZSTD_isError(frame)) throw zstd_error(std::string("corrupt zstd data: ") + ZSTD_getErrorName(frame), path, offset);
    const std::size_t n = ZSTD_decompressDCtx(ctx, out.data() + produced, size - produced, bytes.data() + in, frame);
    if (ZSTD_isError(n)) {
      if (ZSTD_getErrorCode(n) == ZSTD_error_dstSize_tooSmall)
        throw zstd_error("zstd data longer than the announced " + std::to_string(size) + " bytes", path, offset);
      throw zstd_error(std::string("corrupt zstd data: ") + ZSTD_getErrorName(n), path, offset);
    }
    produced += n;
    in += frame;
  }
  if (produced != size)
    throw zstd_error("zstd data of " + std::to_string(produced) + " bytes, announced " + std::to_string(size), path, offset);
  return out;
}

std::string zstd_decompress_any(std::string_view bytes, const std::string& path, std::size_t offset, std::size_t max_bytes) {
  std::unique_ptr<ZSTD_DStream, std::size_t (*)(ZSTD_DStream*)> stream(ZSTD_createDStream(), ZSTD_freeDStream);
  if (!stream) throw zstd_error("cannot start the zstd decoder", path, offset);
  ZSTD_initDStream(stream.get());
  std::string out;
  std::string buffer(ZSTD_DStreamOutSize(), '\0');
  ZSTD_inBuffer in{bytes.data(), bytes.size(), 0};
  std::size_t last = 1;
  while (in.pos < in.size) {
    ZSTD_outBuffer o{buffer.data(), buffer.size(), 0};
    last = ZSTD_decompressStream(stream.get(), &o, &in);
    if (ZSTD_isError(last)) throw zstd_error(std::string("corrupt zstd data: ") + ZSTD_getErrorName(last), path, offset);
    // The cap is checked before the output grows past it.
    if (o.pos > max_bytes - out.size())
      throw zstd_error("decompresses to more than " + std::to_string(max_bytes) + " bytes", path, offset);
    out.append(buffer.data(), o.pos);
    if (o.pos == 0 && in.pos == in.size) break;
  }
  // Flush what the decoder still holds.
  while (last != 0) {
    ZSTD_outBuffer o{buffer.data(), buffer.size(), 0};
    last = ZSTD_decompressStream(stream.get(), &o, &in);
    if (ZSTD_isError(last)) throw zstd_error(std::string("corrupt zstd data: ") + ZSTD_getErrorName(last), path, offset);
    if (o.pos > max_bytes - out.size())
      throw zstd_error("decompresses to more than " + std::to_string(max_bytes) + " bytes", path, offset);
    out.append(buffer.data(), o.pos);
    if (o.pos == 0) {
      if (last != 0) throw zstd_error("zstd data ends inside a frame", path, offset);
      break;
    }
  }
  return out;
}

std::string zstd_compress(std::string_view bytes, int level) {
  std::string out(ZSTD_compressBound(bytes.size()), '\0');
  const std::size_t n = ZSTD_compress(out.data(), out.size(), bytes.data(), bytes.size(), level);
  if (ZSTD_isError(n)) throw Error(std::string("zstd compression failed: ") + ZSTD_getErrorName(n));
  out.resize(n);
  return out;
}

}  // namespace starnav
