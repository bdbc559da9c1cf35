// OpenIGTLink (protocol 2) messages bcassim sends and receives, packed and unpacked with Debian's
// libopenigtlink: tracked points in (POINT), hidden points with their 95 % radius out (POINT) and
// the deformed surface out (POLYDATA). Everything here is in SI units (m, s); on the wire
// positions and radii are millimetres, as OpenIGTLink and 3D Slicer use.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace bcassim {

// Size of every OpenIGTLink header, bytes.
inline constexpr std::size_t kIgtlHeaderSize = 58;
// The largest message body bcassim reads (a POINT of ~1.5 million elements); beyond it the
// connection cannot be trusted and is closed.
inline constexpr std::uint64_t kIgtlMaxBodyBytes = 64u << 20;

struct IgtlHeader {
  std::string type;    // e.g. "POINT"
  std::string device;  // the sender's name for the data, e.g. "Markers"
  double time = 0.0;   // the header's time stamp, s
  std::uint64_t bodySize = 0;
};

// Throws InputError ("OpenIGTLink header: ...") for a header of another version.
IgtlHeader decodeIgtlHeader(const unsigned char* bytes);

// One named point of a POINT message.
struct NamedPoint {
  std::string name;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // m
  double radius = 0.0;                                 // m
};

// The points of a POINT message's body (the header's 58 bytes, then bodySize bytes). Throws
// InputError naming the device for a failed CRC or a body that is not whole elements.
std::vector<NamedPoint> decodeIgtlPoints(const unsigned char* header, const unsigned char* body);

// The points of a POLYDATA message's body (its cells and attributes are ignored), in order and
// unnamed. Throws InputError naming the device for a failed CRC or a body shorter than its
// points.
std::vector<NamedPoint> decodeIgtlPolyDataPoints(const unsigned char* header,
                                                 const unsigned char* body);

// A POINT message: device name, time stamp (s), group name shown by 3D Slicer, and the points.
std::string encodeIgtlPoints(const std::string& device, double time, const std::string& group,
                             const std::vector<NamedPoint>& points);

// A POLYDATA message with the triangles `faces` over `vertices` (m).
std::string encodeIgtlSurface(const std::string& device, double time,
                              const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces);

// The markers of one frame from a POINT message's points: when every name is "marker_<i>" (or a
// plain integer i), point i is marker i and markers not named are missing (NaN); otherwise the
// points are markers 0, 1, ... in order. A non-finite position is a missing marker. Throws
// InputError for more points than markers, an index out of range or a marker named twice.
Eigen::MatrixX3d markersFromPoints(const std::vector<NamedPoint>& points, int numMarkers);

}  // namespace bcassim
