// libFuzzer target: OpenIGTLink messages as `bcassim serve` receives them from the network: the
// 58-byte header, then the body it announces, through decodeIgtlHeader, decodeIgtlPoints or
// decodeIgtlPolyDataPoints and markersFromPoints. When the input's first byte is odd, the header's
// CRC is recomputed over the body before decoding, so that mutations reach the body parsers
// instead of stopping at the checksum (the server checks it first too).
#include <igtl_util.h>

#include <cstring>
#include <vector>

#include "FuzzInput.h"
#include "bcassim/stream/IgtlMessages.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace bcassim;
  if (size < 1 + kIgtlHeaderSize) return 0;
  const bool fixCrc = data[0] & 1;
  std::vector<unsigned char> header(data + 1, data + 1 + kIgtlHeaderSize);
  fuzz::expectOnlyInputErrors([&] {
    const IgtlHeader h = decodeIgtlHeader(header.data());
    const std::size_t available = size - 1 - kIgtlHeaderSize;
    // The server reads exactly the announced body, and refuses bodies beyond its limit.
    if (h.bodySize > kIgtlMaxBodyBytes || h.bodySize > available) return;
    // A buffer of exactly the body's size, so that any read past it is a finding.
    std::vector<unsigned char> body(data + 1 + kIgtlHeaderSize,
                                    data + 1 + kIgtlHeaderSize + h.bodySize);
    if (fixCrc) {
      std::uint64_t crc = crc64(body.data(), body.size(), 0);
      for (int i = 57; i >= 50; --i, crc >>= 8) header[i] = static_cast<unsigned char>(crc & 0xff);
    }
    std::vector<NamedPoint> points;
    if (h.type == "POINT")
      points = decodeIgtlPoints(header.data(), body.data());
    else if (h.type == "POLYDATA")
      points = decodeIgtlPolyDataPoints(header.data(), body.data());
    else
      return;
    markersFromPoints(points, 16);
  });
  return 0;
}
