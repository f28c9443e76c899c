// pybind11 module grasp_pipeline._pcl_io — point-cloud files through PCL's own reader and
// writer (libpcl_io). It is a separate extension so that the perception core `_core` does
// not load libpcl_io's VTK dependencies; only `grasp_pipeline.io` imports this one.
//
//   load_pcd(path) -> (points float32 (N, 3), width, height)
//       Any PCD version/encoding PCL reads (ascii, binary, binary_compressed). Organized
//       clouds keep their NaN rows and width x height (N = width * height, row-major).
//   save_pcd(path, points, width=None, height=None, encoding="binary_compressed")
//       Fields x y z (FLOAT32). width/height default to an unorganized N x 1 cloud.
//   load_ply(path) -> points float32 (N, 3)   (the vertices' x/y/z)
//
// x/y/z may be stored with any numeric PCL field type; they are converted to float32.
// Errors never crash the interpreter: a missing file raises FileNotFoundError, a file PCL
// cannot parse or one without x/y/z raises ValueError, a failed write raises OSError,
// bad arguments raise ValueError/TypeError — each message names the file.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <pcl/PCLPointCloud2.h>
#include <pcl/PCLPointField.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace py = pybind11;
namespace fs = std::filesystem;

namespace {

struct FileMissing : std::runtime_error {
  using std::runtime_error::runtime_error;
};
struct WriteFailed : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void require_readable_file(const std::string& path, const char* what) {
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (ec || !fs::exists(status)) throw FileMissing(std::string(what) + " file not found: " + path);
  if (fs::is_directory(status))
    throw std::invalid_argument(std::string(what) + " path is a directory, not a file: " + path);
}

/// Read one numeric field value as double (type checked by the caller).
double read_value(const std::uint8_t* p, std::uint8_t type) {
  switch (type) {
    case pcl::PCLPointField::INT8: { std::int8_t v; std::memcpy(&v, p, 1); return v; }
    case pcl::PCLPointField::UINT8: { std::uint8_t v; std::memcpy(&v, p, 1); return v; }
    case pcl::PCLPointField::INT16: { std::int16_t v; std::memcpy(&v, p, 2); return v; }
    case pcl::PCLPointField::UINT16: { std::uint16_t v; std::memcpy(&v, p, 2); return v; }
    case pcl::PCLPointField::INT32: { std::int32_t v; std::memcpy(&v, p, 4); return v; }
    case pcl::PCLPointField::UINT32: { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
    case pcl::PCLPointField::INT64: { std::int64_t v; std::memcpy(&v, p, 8); return double(v); }
    case pcl::PCLPointField::UINT64: { std::uint64_t v; std::memcpy(&v, p, 8); return double(v); }
    case pcl::PCLPointField::FLOAT32: { float v; std::memcpy(&v, p, 4); return v; }
    case pcl::PCLPointField::FLOAT64: { double v; std::memcpy(&v, p, 8); return v; }
    default: return std::nan("");
  }
}

std::size_t type_size(std::uint8_t type) {
  switch (type) {
    case pcl::PCLPointField::INT8: case pcl::PCLPointField::UINT8: return 1;
    case pcl::PCLPointField::INT16: case pcl::PCLPointField::UINT16: return 2;
    case pcl::PCLPointField::INT32: case pcl::PCLPointField::UINT32:
    case pcl::PCLPointField::FLOAT32: return 4;
    case pcl::PCLPointField::INT64: case pcl::PCLPointField::UINT64:
    case pcl::PCLPointField::FLOAT64: return 8;
    default: return 0;
  }
}

/// What the PCD header declares, checked before PCL's reader runs: PCL 1.13's
/// PCDReader::read dereferences garbage on files without a DATA line or with a truncated
/// body, so anything that is not a well-formed header + enough data is refused here.
struct PcdHeader {
  std::string data;          ///< ascii | binary | binary_compressed
  long long points = -1;     ///< POINTS (or WIDTH * HEIGHT)
  std::size_t record = 0;    ///< bytes per point (sum of SIZE * COUNT)
  std::size_t data_start = 0;
};

std::string printable(const std::string& line) {
  std::string out;
  for (char ch : line.substr(0, 40)) out += (ch >= 32 && ch < 127) ? ch : '?';
  return out + (line.size() > 40 ? "..." : "");
}

std::vector<std::string> split_ws(const std::string& line) {
  std::vector<std::string> tok;
  std::istringstream is(line);
  for (std::string t; is >> t;) tok.push_back(t);
  return tok;
}

PcdHeader check_pcd_header(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot open the file for reading");
  in.seekg(0, std::ios::end);
  const auto file_size = static_cast<std::size_t>(in.tellg());
  in.seekg(0, std::ios::beg);
  const auto bad = [&](const std::string& why) {
    return std::invalid_argument(path + ": not a readable PCD file (" + why + ")");
  };
  PcdHeader h;
  std::vector<long long> sizes, counts;
  long long width = -1, height = 1;
  bool fields = false;
  std::string line;
  for (int lines = 0; std::getline(in, line); ++lines) {
    if (lines > 10000) throw bad("no DATA line in the first 10000 lines");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto tok = split_ws(line);
    if (tok.empty() || tok[0][0] == '#') continue;
    const std::string& key = tok[0];
    const auto num = [&](const std::string& t) {
      try {
        std::size_t used = 0;
        const long long v = std::stoll(t, &used);
        if (used != t.size() || v < 0) throw std::invalid_argument(t);
        return v;
      } catch (const std::logic_error&) {
        throw bad("malformed header line '" + printable(line) + "'");
      }
    };
    if (key == "VERSION" || key == "TYPE" || key == "VIEWPOINT") {
    } else if (key == "FIELDS" || key == "COLUMNS") {
      fields = tok.size() > 1;
    } else if (key == "SIZE") {
      for (std::size_t i = 1; i < tok.size(); ++i) sizes.push_back(num(tok[i]));
    } else if (key == "COUNT") {
      for (std::size_t i = 1; i < tok.size(); ++i) counts.push_back(num(tok[i]));
    } else if (key == "WIDTH" && tok.size() > 1) {
      width = num(tok[1]);
    } else if (key == "HEIGHT" && tok.size() > 1) {
      height = num(tok[1]);
    } else if (key == "POINTS" && tok.size() > 1) {
      h.points = num(tok[1]);
    } else if (key == "DATA" && tok.size() > 1) {
      h.data = tok[1];
      h.data_start = static_cast<std::size_t>(in.tellg());
      break;
    } else {
      throw bad("unexpected header line '" + printable(line) + "'");
    }
  }
  if (h.data.empty()) throw bad("no DATA line: the header is incomplete or this is not a PCD file");
  if (h.data != "ascii" && h.data != "binary" && h.data != "binary_compressed")
    throw bad("unknown DATA encoding '" + printable(h.data) + "'");
  if (!fields) throw bad("no FIELDS line");
  if (h.points < 0) h.points = width >= 0 ? width * height : -1;
  if (h.points < 0) throw bad("neither POINTS nor WIDTH given");
  if (width >= 0 && width * height != h.points)
    throw bad("WIDTH x HEIGHT = " + std::to_string(width * height) + " but POINTS = " +
              std::to_string(h.points));
  if (sizes.empty()) throw bad("no SIZE line");
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    const long long c = i < counts.size() ? counts[i] : 1;
    if (sizes[i] <= 0 || c <= 0) throw bad("non-positive SIZE or COUNT");
    h.record += static_cast<std::size_t>(sizes[i] * c);
  }
  const std::size_t avail = file_size > h.data_start ? file_size - h.data_start : 0;
  if (h.data == "binary" && avail < static_cast<std::size_t>(h.points) * h.record)
    throw bad("truncated binary data: " + std::to_string(avail) + " bytes, " +
              std::to_string(static_cast<std::size_t>(h.points) * h.record) + " expected");
  if (h.data == "binary_compressed" && h.points > 0) {
    std::uint32_t sz[2] = {0, 0};
    if (avail < 8 || !in.read(reinterpret_cast<char*>(sz), 8))
      throw bad("truncated compressed data");
    if (sz[0] > avail - 8) throw bad("truncated compressed data");
    if (sz[1] != static_cast<std::size_t>(h.points) * h.record)
      throw bad("compressed block does not match the header's point count");
  }
  return h;
}

/// The x/y/z fields of a PCLPointCloud2 as an (N, 3) float32 array (N = width * height).
py::array_t<float> xyz_of(const pcl::PCLPointCloud2& cloud, const std::string& path) {
  const pcl::PCLPointField* f[3] = {nullptr, nullptr, nullptr};
  const char* names[3] = {"x", "y", "z"};
  std::string have;
  for (const auto& field : cloud.fields) {
    have += (have.empty() ? "" : " ") + field.name;
    for (int k = 0; k < 3; ++k)
      if (field.name == names[k] && f[k] == nullptr) f[k] = &field;
  }
  for (int k = 0; k < 3; ++k) {
    if (f[k] == nullptr)
      throw std::invalid_argument(path + ": no '" + names[k] + "' field (fields: " +
                                  (have.empty() ? "none" : have) +
                                  "); a point cloud needs x, y and z");
    if (type_size(f[k]->datatype) == 0)
      throw std::invalid_argument(path + ": field '" + names[k] + "' has an unsupported type " +
                                  std::to_string(int(f[k]->datatype)));
    if (std::size_t(f[k]->offset) + type_size(f[k]->datatype) > cloud.point_step)
      throw std::invalid_argument(path + ": field '" + names[k] + "' lies outside the point record");
  }
  const std::size_t n = std::size_t(cloud.width) * std::size_t(cloud.height);
  const std::size_t step = cloud.point_step;
  if (n > 0 && (step == 0 || cloud.data.size() < n * step))
    throw std::invalid_argument(path + ": truncated data (" + std::to_string(cloud.data.size()) +
                                " bytes for " + std::to_string(n) + " points of " +
                                std::to_string(step) + " bytes)");
  py::array_t<float> out({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(3)});
  float* dst = out.mutable_data();
  const std::uint8_t* src = cloud.data.data();
  // Organized clouds: row r, column c is point r * width + c; PCL's row_step == width * step.
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* rec = src + i * step;
    for (int k = 0; k < 3; ++k) {
      if (f[k]->datatype == pcl::PCLPointField::FLOAT32) {
        std::memcpy(dst + 3 * i + k, rec + f[k]->offset, 4);
      } else {
        dst[3 * i + k] = static_cast<float>(read_value(rec + f[k]->offset, f[k]->datatype));
      }
    }
  }
  return out;
}

py::tuple load_pcd(const std::string& path) {
  require_readable_file(path, "PCD");
  const PcdHeader header = check_pcd_header(path);
  pcl::PCLPointCloud2 cloud;
  int result = -1;
  std::string why;
  {
    py::gil_scoped_release release;
    try {
      pcl::PCDReader reader;
      Eigen::Vector4f origin;
      Eigen::Quaternionf orientation;
      int version = 0;
      if (header.points == 0) {  // PCL refuses empty bodies; keep the declared fields
        int data_type = 0;
        unsigned int data_idx = 0;
        result = reader.readHeader(path, cloud, origin, orientation, version, data_type, data_idx);
        cloud.data.clear();
        if (result >= 0) result = 0;
      } else {
        result = reader.read(path, cloud, origin, orientation, version, 0);
      }
    } catch (const std::exception& e) {
      why = e.what();
      result = -1;
    }
  }
  if (result < 0)
    throw std::invalid_argument(path + ": not a readable PCD file" +
                                (why.empty() ? std::string() : " (" + why + ")") +
                                " — PCL's reader rejected the header or the data");
  auto pts = xyz_of(cloud, path);
  return py::make_tuple(pts, cloud.width, cloud.height);
}

py::array_t<float> load_ply(const std::string& path) {
  require_readable_file(path, "PLY");
  pcl::PCLPointCloud2 cloud;
  int result = -1;
  std::string why;
  {
    py::gil_scoped_release release;
    try {
      pcl::PLYReader reader;
      Eigen::Vector4f origin;
      Eigen::Quaternionf orientation;
      int version = 0;
      result = reader.read(path, cloud, origin, orientation, version, 0);
    } catch (const std::exception& e) {
      why = e.what();
      result = -1;
    }
  }
  if (result < 0)
    throw std::invalid_argument(path + ": not a readable PLY file" +
                                (why.empty() ? std::string() : " (" + why + ")") +
                                " — PCL's reader rejected the header or the data");
  return xyz_of(cloud, path);
}

void save_pcd(const std::string& path, const py::object& points_obj, std::optional<long long> width,
              std::optional<long long> height, const std::string& encoding) {
  if (encoding != "binary_compressed" && encoding != "binary" && encoding != "ascii")
    throw std::invalid_argument("encoding must be 'binary_compressed', 'binary' or 'ascii', got '" +
                                encoding + "'");
  if (!py::isinstance<py::array>(points_obj))
    throw py::type_error("points: expected a numpy array of shape (N, 3)");
  py::array raw = py::reinterpret_borrow<py::array>(points_obj);
  if (raw.dtype().kind() != 'f' && raw.dtype().kind() != 'i' && raw.dtype().kind() != 'u')
    throw py::type_error("points: expected a numeric dtype, got " +
                         py::str(raw.dtype()).cast<std::string>());
  auto pts = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(raw);
  if (!pts) throw py::type_error("points: cannot convert to float32");
  if (pts.ndim() != 2 || pts.shape(1) != 3)
    throw std::invalid_argument("points: expected shape (N, 3) (an organized H x W x 3 cloud can "
                                "be passed as points.reshape(-1, 3) with width=W, height=H)");
  const long long n = pts.shape(0);
  long long w = width.value_or(height ? (*height > 0 ? n / *height : 0) : n);
  long long h = height.value_or(w > 0 ? n / w : 1);
  if (w <= 0 || h <= 0 || w * h != n || w > 0xFFFFFFFFLL || h > 0xFFFFFFFFLL)
    throw std::invalid_argument("width x height must equal the number of points: " +
                                std::to_string(w) + " x " + std::to_string(h) + " != " +
                                std::to_string(n) + (n == 0 ? " (an empty cloud cannot be saved)" : ""));

  pcl::PCLPointCloud2 cloud;
  cloud.width = static_cast<std::uint32_t>(w);
  cloud.height = static_cast<std::uint32_t>(h);
  cloud.is_bigendian = false;
  cloud.point_step = 12;
  cloud.row_step = cloud.point_step * cloud.width;
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    pcl::PCLPointField f;
    f.name = names[k];
    f.offset = 4 * k;
    f.datatype = pcl::PCLPointField::FLOAT32;
    f.count = 1;
    cloud.fields.push_back(f);
  }
  cloud.data.resize(std::size_t(n) * 12);
  std::memcpy(cloud.data.data(), pts.data(), cloud.data.size());
  bool dense = true;
  const float* p = pts.data();
  for (long long i = 0; i < 3 * n && dense; ++i) dense = std::isfinite(p[i]);
  cloud.is_dense = dense;

  int result = -1;
  std::string why;
  {
    py::gil_scoped_release release;
    try {
      pcl::PCDWriter writer;
      const Eigen::Vector4f origin = Eigen::Vector4f::Zero();
      const Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
      if (encoding == "binary_compressed")
        result = writer.writeBinaryCompressed(path, cloud, origin, orientation);
      else if (encoding == "binary")
        result = writer.writeBinary(path, cloud, origin, orientation);
      else
        result = writer.writeASCII(path, cloud, origin, orientation, 9);  // 9 digits: exact float32
    } catch (const std::exception& e) {
      why = e.what();
      result = -1;
    }
  }
  if (result < 0)
    throw WriteFailed(path + ": PCL could not write the PCD file" +
                      (why.empty() ? std::string() : " (" + why + ")") +
                      " — does the directory exist and is it writable?");
}

}  // namespace

PYBIND11_MODULE(_pcl_io, m) {
  m.doc() = "Point-cloud files through PCL's reader/writer (PCD: ascii/binary/binary_compressed; PLY)";
  py::register_exception<FileMissing>(m, "FileMissingError", PyExc_FileNotFoundError);
  py::register_exception<WriteFailed>(m, "WriteFailedError", PyExc_OSError);
  m.def("load_pcd", &load_pcd, py::arg("path"),
        "Read a PCD file -> (points float32 (N, 3), width, height); NaN rows of organized "
        "clouds are kept (N = width * height).");
  m.def("save_pcd", &save_pcd, py::arg("path"), py::arg("points"), py::arg("width") = py::none(),
        py::arg("height") = py::none(), py::arg("encoding") = "binary_compressed",
        "Write (N, 3) points as a PCD file with fields x y z (float32). width x height must "
        "equal N (default N x 1). encoding: 'binary_compressed' (default), 'binary', 'ascii'.");
  m.def("load_ply", &load_ply, py::arg("path"),
        "Read the vertices of a PLY file (ascii or binary) -> points float32 (N, 3).");
  m.attr("PCL_VERSION") = PCL_VERSION_PRETTY;
}
