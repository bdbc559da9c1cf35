#include "bcassim/stream/IgtlMessages.h"

#include <fmt/format.h>
#include <igtlMessageHeader.h>
#include <igtlPointMessage.h>
#include <igtlPolyDataMessage.h>
#include <igtl_point.h>
#include <igtl_util.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "bcassim/Error.h"

namespace bcassim {

namespace {

constexpr double kMmPerM = 1e3;

void setTime(igtl::MessageBase& m, double time) {
  const double seconds = std::floor(std::max(time, 0.0));
  // The fraction is a 32-bit fixed-point number of 2^-32 s (OpenIGTLink's time stamp).
  const double fraction = std::ldexp(std::max(time, 0.0) - seconds, 32);
  m.SetTimeStamp(static_cast<unsigned int>(seconds),
                 static_cast<unsigned int>(std::min(fraction, 4294967295.0)));
}

std::string bytesOf(igtl::MessageBase& m) {
  m.Pack();
  return std::string(static_cast<const char*>(m.GetPackPointer()),
                     static_cast<std::size_t>(m.GetPackSize()));
}

// A name from the wire as it may appear in a one-line message: bytes outside printable ASCII
// (a newline, a terminal escape) written as \xNN.
std::string printable(const std::string& raw) {
  std::string out;
  for (const char c : raw) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7f)
      out += c;
    else
      out += fmt::format("\\x{:02x}", byte);
  }
  return out;
}

// The body's CRC-64 as the header announces it (bytes 50-57, big-endian).
std::uint64_t headerCrc(const unsigned char* header) {
  std::uint64_t crc = 0;
  for (int i = 50; i < 58; ++i) crc = crc << 8 | header[i];
  return crc;
}

// "marker_<i>" or "<i>" -> i; -1 otherwise.
long markerIndexOf(const std::string& name) {
  std::string digits = name;
  if (name.rfind("marker_", 0) == 0) digits = name.substr(7);
  if (digits.empty() || digits.size() > 9) return -1;
  for (char c : digits)
    if (c < '0' || c > '9') return -1;
  return std::stol(digits);
}

}  // namespace

IgtlHeader decodeIgtlHeader(const unsigned char* bytes) {
  igtl::MessageHeader::Pointer h = igtl::MessageHeader::New();
  h->InitPack();
  std::memcpy(h->GetPackPointer(), bytes, kIgtlHeaderSize);
  h->Unpack();
  const auto version = static_cast<unsigned>(bytes[0]) << 8 | bytes[1];
  if (version != 1 && version != 2)
    throw InputError(fmt::format(
        "OpenIGTLink header: version {} (expected 1 or 2, the protocol of libopenigtlink 1.11)",
        version));
  IgtlHeader out;
  out.type = printable(h->GetDeviceType());
  out.device = printable(h->GetDeviceName());
  unsigned int sec = 0, frac = 0;
  h->GetTimeStamp(&sec, &frac);
  out.time = sec + std::ldexp(static_cast<double>(frac), -32);
  // Read here, not by the library, whose int would wrap a large announced size.
  out.bodySize = 0;
  for (int i = 42; i < 50; ++i) out.bodySize = out.bodySize << 8 | bytes[i];
  return out;
}

std::vector<NamedPoint> decodeIgtlPoints(const unsigned char* header, const unsigned char* body) {
  igtl::MessageHeader::Pointer h = igtl::MessageHeader::New();
  h->InitPack();
  std::memcpy(h->GetPackPointer(), header, kIgtlHeaderSize);
  h->Unpack();
  const std::string device = printable(h->GetDeviceName());
  const std::uint64_t size = decodeIgtlHeader(header).bodySize;
  if (size % IGTL_POINT_ELEMENT_SIZE != 0)
    throw InputError(fmt::format("POINT '{}': body of {} bytes is not whole {}-byte elements",
                                 device, size, IGTL_POINT_ELEMENT_SIZE));
  if (size == 0) {
    // A frame without points (every marker hidden). The library's unpacking reports an empty
    // body as a failed CRC; the CRC of no bytes is 0.
    if (headerCrc(header) != 0)
      throw InputError(fmt::format("POINT '{}': the body's CRC does not match its header", device));
    return {};
  }
  igtl::PointMessage::Pointer m = igtl::PointMessage::New();
  m->SetMessageHeader(h);
  m->AllocatePack();
  std::memcpy(m->GetPackBodyPointer(), body, size);
  if (!(m->Unpack(1) & igtl::MessageHeader::UNPACK_BODY))
    throw InputError(fmt::format("POINT '{}': the body's CRC does not match its header", device));
  std::vector<NamedPoint> points(static_cast<std::size_t>(m->GetNumberOfPointElement()));
  for (std::size_t i = 0; i < points.size(); ++i) {
    igtl::PointElement::Pointer e;
    m->GetPointElement(static_cast<int>(i), e);
    igtlFloat32 p[3];
    e->GetPosition(p);
    points[i].name = printable(e->GetName());
    points[i].position = Eigen::Vector3d(p[0], p[1], p[2]) / kMmPerM;
    points[i].radius = e->GetRadius() / kMmPerM;
  }
  return points;
}

std::vector<NamedPoint> decodeIgtlPolyDataPoints(const unsigned char* header,
                                                 const unsigned char* body) {
  // Read here rather than by the library's unpacking, which trusts the body's counts: the CRC,
  // then the point count (first of ten big-endian uint32 counts) and the float32 points.
  const IgtlHeader h = decodeIgtlHeader(header);
  if (crc64(const_cast<unsigned char*>(body), h.bodySize, 0) != headerCrc(header))
    throw InputError(
        fmt::format("POLYDATA '{}': the body's CRC does not match its header", h.device));
  const auto uint32At = [&](std::uint64_t at) {
    return static_cast<std::uint32_t>(body[at]) << 24 |
           static_cast<std::uint32_t>(body[at + 1]) << 16 |
           static_cast<std::uint32_t>(body[at + 2]) << 8 | body[at + 3];
  };
  constexpr std::uint64_t kCounts = 40;
  if (h.bodySize < kCounts)
    throw InputError(fmt::format("POLYDATA '{}': body of {} bytes, shorter than its {}-byte header",
                                 h.device, h.bodySize, kCounts));
  const std::uint64_t n = uint32At(0);
  if (h.bodySize < kCounts + 12 * n)
    throw InputError(fmt::format("POLYDATA '{}': {} points do not fit in its body of {} bytes",
                                 h.device, n, h.bodySize));
  std::vector<NamedPoint> points(n);
  for (std::uint64_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t bits = uint32At(kCounts + 12 * i + 4 * static_cast<std::uint64_t>(c));
      float v = 0;
      std::memcpy(&v, &bits, sizeof v);
      points[i].position(c) = v / kMmPerM;
    }
  return points;
}

std::string encodeIgtlPoints(const std::string& device, double time, const std::string& group,
                             const std::vector<NamedPoint>& points) {
  igtl::PointMessage::Pointer m = igtl::PointMessage::New();
  m->SetDeviceName(device.c_str());
  setTime(*m, time);
  for (const NamedPoint& p : points) {
    igtl::PointElement::Pointer e = igtl::PointElement::New();
    e->SetName(p.name.c_str());
    e->SetGroupName(group.c_str());
    e->SetRGBA(230, 60, 60, 255);
    e->SetPosition(static_cast<igtlFloat32>(kMmPerM * p.position.x()),
                   static_cast<igtlFloat32>(kMmPerM * p.position.y()),
                   static_cast<igtlFloat32>(kMmPerM * p.position.z()));
    e->SetRadius(static_cast<igtlFloat32>(kMmPerM * p.radius));
    m->AddPointElement(e);
  }
  return bytesOf(*m);
}

std::string encodeIgtlSurface(const std::string& device, double time,
                              const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces) {
  igtl::PolyDataPointArray::Pointer points = igtl::PolyDataPointArray::New();
  for (Eigen::Index i = 0; i < vertices.rows(); ++i)
    points->AddPoint(static_cast<igtlFloat32>(kMmPerM * vertices(i, 0)),
                     static_cast<igtlFloat32>(kMmPerM * vertices(i, 1)),
                     static_cast<igtlFloat32>(kMmPerM * vertices(i, 2)));
  igtl::PolyDataCellArray::Pointer polygons = igtl::PolyDataCellArray::New();
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    igtlUint32 cell[3] = {static_cast<igtlUint32>(faces(f, 0)),
                          static_cast<igtlUint32>(faces(f, 1)),
                          static_cast<igtlUint32>(faces(f, 2))};
    polygons->AddCell(3, cell);
  }
  igtl::PolyDataMessage::Pointer m = igtl::PolyDataMessage::New();
  m->SetDeviceName(device.c_str());
  setTime(*m, time);
  m->SetPoints(points);
  m->SetPolygons(polygons);
  return bytesOf(*m);
}

Eigen::MatrixX3d markersFromPoints(const std::vector<NamedPoint>& points, int numMarkers) {
  Eigen::MatrixX3d out =
      Eigen::MatrixX3d::Constant(numMarkers, 3, std::numeric_limits<double>::quiet_NaN());
  bool named = !points.empty();
  for (const NamedPoint& p : points) named = named && markerIndexOf(p.name) >= 0;
  if (!named && static_cast<long>(points.size()) > numMarkers)
    throw InputError(
        fmt::format("{} points for the scene's {} markers", points.size(), numMarkers));
  std::vector<bool> seen(static_cast<std::size_t>(numMarkers), false);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const long k = named ? markerIndexOf(points[i].name) : static_cast<long>(i);
    if (k >= numMarkers)
      throw InputError(fmt::format("point '{}': marker {} of the scene's {} markers (0 to {})",
                                   points[i].name, k, numMarkers, numMarkers - 1));
    if (seen[static_cast<std::size_t>(k)])
      throw InputError(fmt::format("point '{}': marker {} given twice", points[i].name, k));
    seen[static_cast<std::size_t>(k)] = true;
    if (points[i].position.allFinite()) out.row(k) = points[i].position.transpose();
  }
  return out;
}

}  // namespace bcassim
