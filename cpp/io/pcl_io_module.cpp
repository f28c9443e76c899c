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
// ASCII bodies (PCD and PLY) are checked line by line before PCL reads them (PCL would
// read a non-number as 0 or NaN): a value that is not a number of its field's type, a line
// with too few/many values, or fewer/more lines than the header declares raise ValueError
// naming the line number and the field ('nan' and 'inf' are numbers).
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

#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
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
  int data_line = 0;                ///< 1-based line number of the DATA line
  std::vector<std::string> names;   ///< FIELDS
  std::vector<long long> sizes;     ///< SIZE
  std::vector<std::string> types;   ///< TYPE (F, I, U)
  std::vector<long long> counts;    ///< COUNT (1 each when absent)
};

std::string printable(const std::string& line) {
  std::string out;
  for (char ch : line.substr(0, 40)) out += (ch >= 32 && ch < 127) ? ch : '?';
  return out + (line.size() > 40 ? "..." : "");
}

/// Whitespace-separated tokens (space, tab, CR, and the other isspace characters).
std::vector<std::string> split_ws(const std::string& line) {
  std::vector<std::string> tok;
  const std::size_t n = line.size();
  for (std::size_t i = 0; i < n;) {
    while (i < n && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const std::size_t start = i;
    while (i < n && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) tok.emplace_back(line, start, i - start);
  }
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
  std::vector<long long>& sizes = h.sizes;
  std::vector<long long>& counts = h.counts;
  long long width = -1, height = 1;
  bool fields = false;
  std::string line;
  for (int lines = 0; std::getline(in, line); ++lines) {
    if (lines > 10000) throw bad("no DATA line in the first 10000 lines");
    h.data_line = lines + 1;
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
    if (key == "VERSION" || key == "VIEWPOINT") {
    } else if (key == "TYPE") {
      h.types.assign(tok.begin() + 1, tok.end());
    } else if (key == "FIELDS" || key == "COLUMNS") {
      fields = tok.size() > 1;
      h.names.assign(tok.begin() + 1, tok.end());
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

// ---- ASCII bodies: PCL's readers turn a token that is not a number into 0 (PCD, via
// atof) or NaN (PLY), skip a PCD line with the wrong number of values (the point stays 0)
// and read PLY values across line ends. Both ASCII bodies are therefore checked here
// first, line by line: every value must be a number of its field's type, every line must
// hold exactly one point (PCD) / one element (PLY), and the line count must match the
// header. Errors name the file, the 1-based line number and the field.

enum class NumKind { kFloat, kSigned, kUnsigned };

/// Why `tok` is not a valid value of a field (empty when it is). Floats: decimal notation
/// [+-]digits[.digits][e[+-]digits], or nan / inf / infinity (any case, optional sign; a
/// PCD NaN is legitimate, an Inf becomes a dropped row downstream) -- no hex, no
/// trailing characters. Integers: [+-]digits within the range of `bytes` bytes.
std::string number_problem(const std::string& tok, NumKind kind, int bytes) {
  std::size_t i = 0;
  const bool neg = !tok.empty() && tok[0] == '-';
  if (!tok.empty() && (tok[0] == '+' || tok[0] == '-')) i = 1;
  if (kind == NumKind::kFloat) {
    std::string rest;
    for (std::size_t k = i; k < tok.size(); ++k) rest += static_cast<char>(std::tolower(tok[k]));
    if (rest == "nan" || rest == "inf" || rest == "infinity") return "";
    std::size_t digits = 0, k = i;
    while (k < tok.size() && std::isdigit(static_cast<unsigned char>(tok[k]))) ++k, ++digits;
    if (k < tok.size() && tok[k] == '.') {
      ++k;
      while (k < tok.size() && std::isdigit(static_cast<unsigned char>(tok[k]))) ++k, ++digits;
    }
    if (digits > 0 && k < tok.size() && (tok[k] == 'e' || tok[k] == 'E')) {
      std::size_t e = k + 1;
      if (e < tok.size() && (tok[e] == '+' || tok[e] == '-')) ++e;
      std::size_t ed = 0;
      while (e < tok.size() && std::isdigit(static_cast<unsigned char>(tok[e]))) ++e, ++ed;
      if (ed > 0) k = e;
    }
    if (digits == 0 || k != tok.size()) return "is not a number";
    return "";
  }
  std::size_t k = i;
  while (k < tok.size() && std::isdigit(static_cast<unsigned char>(tok[k]))) ++k;
  if (k == i || k != tok.size()) return "is not an integer";
  errno = 0;
  if (kind == NumKind::kUnsigned) {
    if (neg && tok.find_first_not_of("-0") != std::string::npos) return "is negative (unsigned field)";
    const unsigned long long v = std::strtoull(tok.c_str() + i, nullptr, 10);
    const unsigned long long hi = bytes >= 8 ? ~0ULL : (1ULL << (8 * bytes)) - 1;
    if (errno == ERANGE || v > hi) return "is out of range for an unsigned " + std::to_string(8 * bytes) + "-bit field";
    return "";
  }
  const long long v = std::strtoll(tok.c_str(), nullptr, 10);
  const long long hi = bytes >= 8 ? LLONG_MAX : (1LL << (8 * bytes - 1)) - 1;
  if (errno == ERANGE || v > hi || v < -hi - 1)
    return "is out of range for a signed " + std::to_string(8 * bytes) + "-bit field";
  return "";
}

/// One column of an ASCII body: its display name and value type.
struct Column {
  std::string name;
  NumKind kind = NumKind::kFloat;
  int bytes = 4;
};

[[noreturn]] void ascii_error(const std::string& path, const char* fmt, int line,
                              const std::string& why) {
  throw std::invalid_argument(path + ": " + fmt + " data, line " + std::to_string(line) + ": " + why);
}

std::string show(const std::string& tok) { return "'" + printable(tok) + "'"; }

/// The PCD DATA ascii body: POINTS lines of sum(COUNT) numbers each (empty lines are skipped,
/// as PCL does).
void check_pcd_ascii_body(const std::string& path, const PcdHeader& h) {
  std::vector<Column> cols;
  for (std::size_t f = 0; f < h.names.size(); ++f) {
    const long long count = f < h.counts.size() ? h.counts[f] : 1;
    const std::string type = f < h.types.size() ? h.types[f] : "F";
    Column c;
    c.kind = type == "F" ? NumKind::kFloat : type == "U" ? NumKind::kUnsigned : NumKind::kSigned;
    c.bytes = static_cast<int>(f < h.sizes.size() ? h.sizes[f] : 4);
    for (long long k = 0; k < count; ++k) {
      c.name = count == 1 ? h.names[f] : h.names[f] + "[" + std::to_string(k) + "]";
      cols.push_back(c);
    }
  }
  std::string names;
  for (const auto& n : h.names) names += (names.empty() ? "" : " ") + n;
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(h.data_start));
  std::string line;
  long long points = 0;
  for (int ln = h.data_line + 1; std::getline(in, line); ++ln) {
    // PCL skips empty lines only: a line of blanks (or a lone CR) is a point for PCL,
    // read as zeros, so it is an error here ("got 0").
    if (line.empty()) continue;
    const auto tok = split_ws(line);
    if (points == h.points)
      ascii_error(path, "PCD ascii", ln, "more data lines than POINTS = " + std::to_string(h.points) +
                  " (the header's point count is wrong or the file has trailing data)");
    if (tok.size() != cols.size())
      ascii_error(path, "PCD ascii", ln, "expected " + std::to_string(cols.size()) +
                  " values (fields " + names + "), got " + std::to_string(tok.size()));
    for (std::size_t c = 0; c < cols.size(); ++c) {
      const std::string why = number_problem(tok[c], cols[c].kind, cols[c].bytes);
      if (!why.empty())
        ascii_error(path, "PCD ascii", ln, "field '" + cols[c].name + "' (column " +
                    std::to_string(c + 1) + "): " + show(tok[c]) + " " + why);
    }
    ++points;
  }
  if (points < h.points)
    throw std::invalid_argument(path + ": PCD ascii data: only " + std::to_string(points) +
                                " data lines, but POINTS = " + std::to_string(h.points) +
                                " (the file is truncated or the header's point count is wrong)");
}

/// PLY: one element (or list) property of the header.
struct PlyProperty {
  std::string name;
  bool list = false;
  Column count;  ///< the list's length type
  Column value;
};
struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> props;
};

bool ply_type(const std::string& t, Column* c) {
  static const std::pair<const char*, std::pair<NumKind, int>> kTypes[] = {
      {"char", {NumKind::kSigned, 1}},    {"int8", {NumKind::kSigned, 1}},
      {"uchar", {NumKind::kUnsigned, 1}}, {"uint8", {NumKind::kUnsigned, 1}},
      {"short", {NumKind::kSigned, 2}},   {"int16", {NumKind::kSigned, 2}},
      {"ushort", {NumKind::kUnsigned, 2}}, {"uint16", {NumKind::kUnsigned, 2}},
      {"int", {NumKind::kSigned, 4}},     {"int32", {NumKind::kSigned, 4}},
      {"uint", {NumKind::kUnsigned, 4}},  {"uint32", {NumKind::kUnsigned, 4}},
      {"float", {NumKind::kFloat, 4}},    {"float32", {NumKind::kFloat, 4}},
      {"double", {NumKind::kFloat, 8}},   {"float64", {NumKind::kFloat, 8}}};
  for (const auto& [name, kb] : kTypes)
    if (t == name) {
      c->kind = kb.first;
      c->bytes = kb.second;
      return true;
    }
  return false;
}

/// The header of an ASCII PLY (false: not ASCII, or a header this check does not
/// understand -- PCL's reader then decides alone).
bool ply_ascii_header(std::ifstream& in, std::vector<PlyElement>* elements, int* header_lines) {
  std::string line;
  int ln = 0;
  bool ascii = false;
  while (std::getline(in, line)) {
    ++ln;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto tok = split_ws(line);
    if (ln == 1) {
      if (tok.size() != 1 || tok[0] != "ply") return false;
      continue;
    }
    if (tok.empty() || tok[0] == "comment" || tok[0] == "obj_info") continue;
    if (tok[0] == "format") {
      ascii = tok.size() >= 2 && tok[1] == "ascii";
      if (!ascii) return false;
    } else if (tok[0] == "element" && tok.size() == 3) {
      PlyElement e;
      e.name = tok[1];
      try {
        e.count = std::stoll(tok[2]);
      } catch (const std::logic_error&) {
        return false;
      }
      if (e.count < 0) return false;
      elements->push_back(e);
    } else if (tok[0] == "property" && !elements->empty()) {
      PlyProperty p;
      if (tok.size() == 5 && tok[1] == "list") {
        p.list = true;
        p.name = tok[4];
        if (!ply_type(tok[2], &p.count) || !ply_type(tok[3], &p.value) ||
            p.count.kind == NumKind::kFloat)
          return false;
      } else if (tok.size() == 3) {
        p.name = tok[2];
        if (!ply_type(tok[1], &p.value)) return false;
      } else {
        return false;
      }
      p.value.name = p.count.name = p.name;
      elements->back().props.push_back(p);
    } else if (tok[0] == "end_header") {
      *header_lines = ln;
      return ascii;
    } else {
      return false;
    }
  }
  return false;
}

/// An ASCII PLY body: each element instance on its own line with exactly its properties'
/// values (a list: its length, then that many values), as many lines as the header says.
void check_ply_ascii(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return;  // PCL reports it
  std::vector<PlyElement> elements;
  int ln = 0;
  if (!ply_ascii_header(in, &elements, &ln)) return;
  std::string line;
  for (const PlyElement& e : elements) {
    for (long long i = 0; i < e.count; ++i) {
      std::vector<std::string> tok;
      while (tok.empty()) {
        if (!std::getline(in, line))
          throw std::invalid_argument(path + ": PLY ascii data: only " + std::to_string(i) +
                                      " of the " + std::to_string(e.count) + " '" + e.name +
                                      "' lines the header declares (the file is truncated)");
        ++ln;
        tok = split_ws(line);
      }
      std::size_t k = 0;
      for (const PlyProperty& p : e.props) {
        long long n = 1;
        if (p.list) {
          if (k >= tok.size())
            ascii_error(path, "PLY ascii", ln, "too few values for element '" + e.name +
                        "' (missing the length of list '" + p.name + "')");
          const std::string why = number_problem(tok[k], p.count.kind, p.count.bytes);
          if (!why.empty())
            ascii_error(path, "PLY ascii", ln, "the length of list '" + p.name + "': " + show(tok[k]) + " " + why);
          n = std::stoll(tok[k++]);
        }
        for (long long j = 0; j < n; ++j, ++k) {
          if (k >= tok.size())
            ascii_error(path, "PLY ascii", ln, "too few values for element '" + e.name + "': got " +
                        std::to_string(tok.size()) + ", property '" + p.name + "' is missing");
          const std::string why = number_problem(tok[k], p.value.kind, p.value.bytes);
          if (!why.empty())
            ascii_error(path, "PLY ascii", ln, "property '" + p.name + "' of element '" + e.name +
                        "': " + show(tok[k]) + " " + why);
        }
      }
      if (k != tok.size())
        ascii_error(path, "PLY ascii", ln, "too many values for element '" + e.name + "': expected " +
                    std::to_string(k) + ", got " + std::to_string(tok.size()));
    }
  }
  while (std::getline(in, line)) {
    ++ln;
    if (!split_ws(line).empty())
      ascii_error(path, "PLY ascii", ln, "data after the last element the header declares");
  }
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
  pcl::PCLPointCloud2 cloud;
  int result = -1;
  std::string why;
  {
    py::gil_scoped_release release;  // our checks raise std::invalid_argument -> ValueError
    const PcdHeader header = check_pcd_header(path);
    if (header.data == "ascii") check_pcd_ascii_body(path, header);
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
    check_ply_ascii(path);
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
