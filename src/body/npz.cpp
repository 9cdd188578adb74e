#include "body/npz.h"

#include <zlib.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/error.h"

namespace s2p {

namespace {

constexpr uint32_t kLocalSig = 0x04034b50, kCentralSig = 0x02014b50, kEndSig = 0x06054b50;

// Element types a .npy may hold, as read from the 'descr' string.
enum class DType { F8, F4, F2, I1, I2, I4, I8, U1, U2, U4, U8, B1 };

struct DTypeInfo {
  DType type;
  size_t size;
};

DTypeInfo parseDType(const std::string& descr, const std::string& what) {
  if (descr.size() < 3) throw FormatError(what + ": unsupported dtype '" + descr + "'");
  const char order = descr[0];
  const std::string code = descr.substr(1);
  if (code == "O")
    throw FormatError(what +
                      ": dtype '|O' (pickled Python objects) is not supported; convert "
                      "the array to a numeric dense array before saving");
  if (order != '<' && order != '|' && order != '=' && order != '>')
    throw FormatError(what + ": unsupported dtype '" + descr + "'");
  static const std::pair<const char*, DTypeInfo> table[] = {
      {"f8", {DType::F8, 8}}, {"f4", {DType::F4, 4}}, {"f2", {DType::F2, 2}},
      {"i1", {DType::I1, 1}}, {"i2", {DType::I2, 2}}, {"i4", {DType::I4, 4}},
      {"i8", {DType::I8, 8}}, {"u1", {DType::U1, 1}}, {"u2", {DType::U2, 2}},
      {"u4", {DType::U4, 4}}, {"u8", {DType::U8, 8}}, {"b1", {DType::B1, 1}}};
  for (const auto& [name, info] : table)
    if (code == name) {
      if (order == '>' && info.size > 1)
        throw FormatError(what + ": big-endian dtype '" + descr +
                          "' is not supported; save little-endian ('<') data");
      return info;
    }
  throw FormatError(what + ": unsupported dtype '" + descr +
                    "' (supported: <f8 <f4 <i4 <i8 <u4 |u1 |b1 and similar)");
}

template <class T>
T loadLe(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));  // x86-64 and aarch64 are little-endian
  return v;
}

double halfToDouble(uint16_t h) {
  const int sign = h >> 15, exp = (h >> 10) & 0x1f, frac = h & 0x3ff;
  double v;
  if (exp == 0)
    v = std::ldexp(frac, -24);
  else if (exp == 31)
    v = frac ? std::numeric_limits<double>::quiet_NaN() : std::numeric_limits<double>::infinity();
  else
    v = std::ldexp(frac + 1024, exp - 25);
  return sign ? -v : v;
}

double loadValue(DType t, const char* p) {
  switch (t) {
    case DType::F8:
      return loadLe<double>(p);
    case DType::F4:
      return loadLe<float>(p);
    case DType::F2:
      return halfToDouble(loadLe<uint16_t>(p));
    case DType::I1:
      return loadLe<int8_t>(p);
    case DType::I2:
      return loadLe<int16_t>(p);
    case DType::I4:
      return loadLe<int32_t>(p);
    case DType::I8:
      return static_cast<double>(loadLe<int64_t>(p));
    case DType::U1:
      return loadLe<uint8_t>(p);
    case DType::U2:
      return loadLe<uint16_t>(p);
    case DType::U4:
      return loadLe<uint32_t>(p);
    case DType::U8:
      return static_cast<double>(loadLe<uint64_t>(p));
    case DType::B1:
      return p[0] != 0 ? 1.0 : 0.0;
  }
  return 0;
}

template <class T>
void storeLe(std::string& out, T v) {
  char buf[sizeof(T)];
  std::memcpy(buf, &v, sizeof(T));
  out.append(buf, sizeof(T));
}

void storeValue(DType t, double v, std::string& out) {
  switch (t) {
    case DType::F8:
      storeLe<double>(out, v);
      break;
    case DType::F4:
      storeLe<float>(out, static_cast<float>(v));
      break;
    case DType::F2:
      throw InputError("encodeNpy: writing float16 is not supported");
    case DType::I1:
      storeLe<int8_t>(out, static_cast<int8_t>(v));
      break;
    case DType::I2:
      storeLe<int16_t>(out, static_cast<int16_t>(v));
      break;
    case DType::I4:
      storeLe<int32_t>(out, static_cast<int32_t>(v));
      break;
    case DType::I8:
      storeLe<int64_t>(out, static_cast<int64_t>(v));
      break;
    case DType::U1:
      storeLe<uint8_t>(out, static_cast<uint8_t>(v));
      break;
    case DType::U2:
      storeLe<uint16_t>(out, static_cast<uint16_t>(v));
      break;
    case DType::U4:
      storeLe<uint32_t>(out, static_cast<uint32_t>(v));
      break;
    case DType::U8:
      storeLe<uint64_t>(out, static_cast<uint64_t>(v));
      break;
    case DType::B1:
      out.push_back(v != 0 ? 1 : 0);
      break;
  }
}

// The value text after 'key': in the header's Python dict literal, or npos.
size_t findKey(const std::string& header, const std::string& key) {
  for (const char q : {'\'', '"'}) {
    const std::string k = std::string(1, q) + key + q;
    size_t p = header.find(k);
    if (p == std::string::npos) continue;
    p = header.find(':', p + k.size());
    if (p == std::string::npos) return p;
    ++p;
    while (p < header.size() && std::isspace(static_cast<unsigned char>(header[p]))) ++p;
    return p;
  }
  return std::string::npos;
}

struct NpyHeader {
  std::string descr;
  bool fortran = false;
  std::vector<size_t> shape;
};

NpyHeader parseHeader(const std::string& h, const std::string& what) {
  NpyHeader out;
  const auto bad = [&](const std::string& why) {
    return FormatError(what + ": malformed .npy header (" + why + "): " + h);
  };
  size_t p = findKey(h, "descr");
  if (p == std::string::npos || p >= h.size()) throw bad("no 'descr'");
  if (h[p] == '[')
    throw FormatError(what + ": structured dtypes are not supported (plain numeric arrays only)");
  const char q = h[p];
  if (q != '\'' && q != '"') throw bad("'descr' is not a string");
  const size_t e = h.find(q, p + 1);
  if (e == std::string::npos) throw bad("unterminated 'descr'");
  out.descr = h.substr(p + 1, e - p - 1);
  p = findKey(h, "fortran_order");
  if (p == std::string::npos) throw bad("no 'fortran_order'");
  if (h.compare(p, 4, "True") == 0)
    out.fortran = true;
  else if (h.compare(p, 5, "False") == 0)
    out.fortran = false;
  else
    throw bad("'fortran_order' is neither True nor False");
  p = findKey(h, "shape");
  if (p == std::string::npos || p >= h.size() || h[p] != '(') throw bad("no 'shape' tuple");
  const size_t close = h.find(')', p);
  if (close == std::string::npos) throw bad("unterminated 'shape'");
  std::string inner = h.substr(p + 1, close - p - 1);
  size_t i = 0;
  while (i < inner.size()) {
    while (i < inner.size() &&
           (std::isspace(static_cast<unsigned char>(inner[i])) || inner[i] == ','))
      ++i;
    if (i >= inner.size()) break;
    if (!std::isdigit(static_cast<unsigned char>(inner[i]))) throw bad("bad 'shape' entry");
    size_t v = 0;
    while (i < inner.size() && std::isdigit(static_cast<unsigned char>(inner[i]))) {
      if (v > (std::numeric_limits<size_t>::max() - 9) / 10) throw bad("'shape' overflows");
      v = v * 10 + static_cast<size_t>(inner[i++] - '0');
    }
    if (i < inner.size() && inner[i] == 'L') ++i;  // Python 2 long suffix
    out.shape.push_back(v);
  }
  return out;
}

std::string shapeText(const std::vector<size_t>& shape) {
  std::string s = "(";
  for (size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  if (shape.size() == 1) s += ",";
  return s + ")";
}

// Element order conversion: Fortran linear index of each C-order element.
template <class F>
void forEachFortranIndex(const std::vector<size_t>& shape, F f) {
  const size_t n = shape.size();
  size_t total = 1;
  for (size_t s : shape) total *= s;
  if (total == 0) return;
  std::vector<size_t> stride(n, 1), idx(n, 0);
  for (size_t k = 1; k < n; ++k) stride[k] = stride[k - 1] * shape[k - 1];
  for (size_t c = 0; c < total; ++c) {
    size_t fi = 0;
    for (size_t k = 0; k < n; ++k) fi += idx[k] * stride[k];
    f(c, fi);
    for (size_t k = n; k-- > 0;) {  // increment the C-order multi-index
      if (++idx[k] < shape[k]) break;
      idx[k] = 0;
    }
  }
}

std::string readAll(const std::filesystem::path& path, const std::string& kind) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw IoError("cannot open " + kind + " '" + path.string() + "': no such file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot open " + kind + " '" + path.string() + "'");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw IoError("cannot read " + kind + " '" + path.string() + "'");
  return ss.str();
}

std::string inflateRaw(const char* data, size_t csize, size_t usize, const std::string& what) {
  if (csize > std::numeric_limits<uInt>::max() || usize > std::numeric_limits<uInt>::max())
    throw FormatError(what + ": entry too large");
  // DEFLATE cannot expand more than 1032:1 (a 258-byte match per ~2 bits), so a declared size
  // beyond that is a corrupt header: refuse it before allocating what it asks for.
  constexpr size_t kMaxDeflateRatio = 1032;
  if (usize > kMaxDeflateRatio * (csize + 1))
    throw FormatError(what + ": corrupt zip entry (declares " + std::to_string(usize) +
                      " bytes from " + std::to_string(csize) + " compressed)");
  std::string out(usize, '\0');
  z_stream zs{};
  if (inflateInit2(&zs, -15) != Z_OK) throw FormatError(what + ": zlib inflateInit2 failed");
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data));
  zs.avail_in = static_cast<uInt>(csize);
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = static_cast<uInt>(usize);
  const int rc = inflate(&zs, Z_FINISH);
  const size_t produced = zs.total_out;
  inflateEnd(&zs);
  if (rc != Z_STREAM_END || produced != usize)
    throw FormatError(what + ": corrupt DEFLATE data (zlib code " + std::to_string(rc) + ")");
  return out;
}

std::string deflateRaw(const std::string& data) {
  z_stream zs{};
  if (deflateInit2(&zs, Z_DEFAULT_COMPRESSION, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw IoError("zlib deflateInit2 failed");
  std::string out(deflateBound(&zs, data.size()), '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  zs.avail_in = static_cast<uInt>(data.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = static_cast<uInt>(out.size());
  const int rc = deflate(&zs, Z_FINISH);
  out.resize(zs.total_out);
  deflateEnd(&zs);
  if (rc != Z_STREAM_END) throw IoError("zlib deflate failed");
  return out;
}

uint32_t crcOf(const std::string& s) {
  return static_cast<uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(s.data()), static_cast<uInt>(s.size())));
}

}  // namespace

size_t NpyArray::size() const {
  size_t n = 1;
  for (size_t s : shape) n *= s;
  return n;
}

double NpyArray::at(std::initializer_list<size_t> index) const {
  size_t lin = 0, k = 0;
  for (size_t i : index) lin = lin * shape[k++] + i;
  return data[lin];
}

NpyArray decodeNpy(const std::string& bytes, const std::string& what) {
  static const char magic[] = "\x93NUMPY";
  if (bytes.size() < 10 || bytes.compare(0, 6, magic, 6) != 0)
    throw FormatError(what + ": not a .npy array (bad magic)");
  const int major = static_cast<unsigned char>(bytes[6]);
  size_t headerLen, start;
  if (major == 1) {
    headerLen = loadLe<uint16_t>(bytes.data() + 8);
    start = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) throw FormatError(what + ": truncated .npy header");
    headerLen = loadLe<uint32_t>(bytes.data() + 8);
    start = 12;
  } else {
    throw FormatError(what + ": unsupported .npy version " + std::to_string(major));
  }
  if (headerLen > bytes.size() - start) throw FormatError(what + ": truncated .npy header");
  const NpyHeader h = parseHeader(bytes.substr(start, headerLen), what);
  const DTypeInfo dt = parseDType(h.descr, what);
  NpyArray out;
  out.shape = h.shape;
  const size_t available = bytes.size() - start - headerLen;
  size_t count = 1;
  for (size_t s : h.shape) {
    if (s != 0 && count > available / s) throw FormatError(what + ": truncated .npy data");
    count *= s;
  }
  if (count > available / dt.size)
    throw FormatError(what + ": truncated .npy data (" + std::to_string(count) + " elements of " +
                      std::to_string(dt.size) + " bytes expected, " + std::to_string(available) +
                      " bytes present)");
  const char* p = bytes.data() + start + headerLen;
  out.data.resize(count);
  if (h.fortran && h.shape.size() > 1) {
    forEachFortranIndex(
        h.shape, [&](size_t c, size_t f) { out.data[c] = loadValue(dt.type, p + f * dt.size); });
  } else {
    for (size_t i = 0; i < count; ++i) out.data[i] = loadValue(dt.type, p + i * dt.size);
  }
  return out;
}

NpyArray readNpy(const std::filesystem::path& path) {
  return decodeNpy(readAll(path, ".npy file"), std::string("'").append(path.string()).append("'"));
}

std::map<std::string, NpyArray> readNpz(const std::filesystem::path& path) {
  const std::string bytes = readAll(path, ".npz file");
  const std::string file = std::string("'").append(path.string()).append("'");
  const size_t n = bytes.size();
  const char* b = bytes.data();
  if (n < 22) throw FormatError(file + ": too short to be a zip (.npz) archive");
  if (loadLe<uint32_t>(b) != kLocalSig && loadLe<uint32_t>(b) != kEndSig)
    throw FormatError(file + ": not a zip (.npz) archive (bad magic)");
  // End of central directory: the last signature within the 64 KiB comment window.
  size_t eocd = std::string::npos;
  for (size_t p = n - 22 + 1; p-- > 0 && n - p <= 22 + 65535;)
    if (loadLe<uint32_t>(b + p) == kEndSig) {
      eocd = p;
      break;
    }
  if (eocd == std::string::npos)
    throw FormatError(file + ": truncated zip archive (no end-of-central-directory record)");
  const uint16_t numEntries = loadLe<uint16_t>(b + eocd + 10);
  const uint32_t cdSize = loadLe<uint32_t>(b + eocd + 12);
  const uint32_t cdOffset = loadLe<uint32_t>(b + eocd + 16);
  if (numEntries == 0xFFFF || cdSize == 0xFFFFFFFFu || cdOffset == 0xFFFFFFFFu)
    throw FormatError(file + ": zip64 archives (over 4 GiB or 65535 entries) are not supported");
  if (static_cast<size_t>(cdOffset) + cdSize > eocd)
    throw FormatError(file + ": truncated or corrupt zip central directory");

  std::map<std::string, NpyArray> out;
  size_t p = cdOffset;
  for (int e = 0; e < numEntries; ++e) {
    if (p + 46 > eocd || loadLe<uint32_t>(b + p) != kCentralSig)
      throw FormatError(file + ": corrupt zip central directory at entry " + std::to_string(e));
    const uint16_t flags = loadLe<uint16_t>(b + p + 8);
    const uint16_t method = loadLe<uint16_t>(b + p + 10);
    const uint32_t crc = loadLe<uint32_t>(b + p + 16);
    uint64_t csize = loadLe<uint32_t>(b + p + 20);
    uint64_t usize = loadLe<uint32_t>(b + p + 24);
    const uint16_t nameLen = loadLe<uint16_t>(b + p + 28);
    const uint16_t extraLen = loadLe<uint16_t>(b + p + 30);
    const uint16_t commentLen = loadLe<uint16_t>(b + p + 32);
    uint64_t local = loadLe<uint32_t>(b + p + 42);
    if (p + 46 + nameLen + extraLen + commentLen > eocd)
      throw FormatError(file + ": corrupt zip central directory at entry " + std::to_string(e));
    const std::string name(b + p + 46, nameLen);
    const std::string what = file + " entry '" + name + "'";
    // Zip64 extra field (numpy writes small entries with it): 64-bit values replace 0xFFFFFFFF.
    if (usize == 0xFFFFFFFFu || csize == 0xFFFFFFFFu || local == 0xFFFFFFFFu) {
      const char* x = b + p + 46 + nameLen;
      const char* xe = x + extraLen;
      bool found = false;
      while (x + 4 <= xe) {
        const uint16_t id = loadLe<uint16_t>(x), len = loadLe<uint16_t>(x + 2);
        if (x + 4 + len > xe) break;
        if (id == 0x0001) {
          const char* v = x + 4;
          const char* ve = v + len;
          for (uint64_t* f : {&usize, &csize, &local})
            if (*f == 0xFFFFFFFFu) {
              if (v + 8 > ve) throw FormatError(what + ": corrupt zip64 extra field");
              *f = loadLe<uint64_t>(v);
              v += 8;
            }
          found = true;
        }
        x += 4 + len;
      }
      if (!found) throw FormatError(what + ": zip64 sizes without a zip64 extra field");
    }
    p += 46 + nameLen + extraLen + commentLen;
    if (flags & 1) throw FormatError(what + ": encrypted zip entries are not supported");
    if (method != 0 && method != 8)
      throw FormatError(what + ": unsupported zip compression method " + std::to_string(method) +
                        " (only STORED and DEFLATED)");
    if (local + 30 > n || loadLe<uint32_t>(b + local) != kLocalSig)
      throw FormatError(what + ": bad local file header");
    const size_t dataStart =
        local + 30 + loadLe<uint16_t>(b + local + 26) + loadLe<uint16_t>(b + local + 28);
    if (dataStart > n || csize > n - dataStart)
      throw FormatError(what + ": truncated zip entry data");
    std::string raw;
    if (method == 0) {
      if (csize != usize) throw FormatError(what + ": STORED entry with mismatched sizes");
      raw.assign(b + dataStart, csize);
    } else {
      raw = inflateRaw(b + dataStart, csize, usize, what);
    }
    if (crcOf(raw) != crc) throw FormatError(what + ": CRC-32 mismatch (corrupt archive)");
    std::string key = name;
    if (key.size() > 4 && key.compare(key.size() - 4, 4, ".npy") == 0)
      key.resize(key.size() - 4);
    else
      continue;  // not an array
    out[key] = decodeNpy(raw, what);
  }
  return out;
}

std::string encodeNpy(const NpyArray& array, const std::string& dtype, bool fortranOrder) {
  const DTypeInfo dt = parseDType(dtype, "encodeNpy");
  if (array.data.size() != array.size())
    throw InputError("encodeNpy: " + std::to_string(array.data.size()) + " values for shape " +
                     shapeText(array.shape));
  std::string header = "{'descr': '" + dtype +
                       "', 'fortran_order': " + (fortranOrder ? "True" : "False") +
                       ", 'shape': " + shapeText(array.shape) + ", }";
  const size_t total = 10 + header.size() + 1;
  header.append((64 - total % 64) % 64, ' ');
  header += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  storeLe<uint16_t>(out, static_cast<uint16_t>(header.size()));
  out += header;
  out.reserve(out.size() + array.data.size() * dt.size);
  if (fortranOrder && array.shape.size() > 1) {
    std::vector<size_t> cOf(array.data.size());
    forEachFortranIndex(array.shape, [&](size_t c, size_t f) { cOf[f] = c; });
    for (size_t f = 0; f < cOf.size(); ++f) storeValue(dt.type, array.data[cOf[f]], out);
  } else {
    for (double v : array.data) storeValue(dt.type, v, out);
  }
  return out;
}

void writeNpz(const std::filesystem::path& path, const std::vector<NpzEntry>& entries) {
  std::string zip, central;
  for (const NpzEntry& e : entries) {
    const std::string name = e.name + ".npy";
    const std::string raw =
        e.rawNpy.empty() ? encodeNpy(e.array, e.dtype, e.fortranOrder) : e.rawNpy;
    const std::string stored = e.deflate ? deflateRaw(raw) : raw;
    const uint32_t crc = crcOf(raw);
    const uint16_t method = e.deflate ? 8 : 0;
    if (zip.size() + stored.size() > 0xFFFFFFF0u)
      throw InputError("writeNpz: archive over 4 GiB (zip64) is not supported");
    const uint32_t offset = static_cast<uint32_t>(zip.size());
    auto common = [&](std::string& s) {
      storeLe<uint16_t>(s, 20);  // version needed
      storeLe<uint16_t>(s, 0);   // flags
      storeLe<uint16_t>(s, method);
      storeLe<uint16_t>(s, 0);     // time
      storeLe<uint16_t>(s, 0x21);  // date: 1980-01-01
      storeLe<uint32_t>(s, crc);
      storeLe<uint32_t>(s, static_cast<uint32_t>(stored.size()));
      storeLe<uint32_t>(s, static_cast<uint32_t>(raw.size()));
      storeLe<uint16_t>(s, static_cast<uint16_t>(name.size()));
      storeLe<uint16_t>(s, 0);  // extra length
    };
    storeLe<uint32_t>(zip, kLocalSig);
    common(zip);
    zip += name;
    zip += stored;
    storeLe<uint32_t>(central, kCentralSig);
    storeLe<uint16_t>(central, 20);  // version made by
    common(central);
    storeLe<uint16_t>(central, 0);  // comment length
    storeLe<uint16_t>(central, 0);  // disk
    storeLe<uint16_t>(central, 0);  // internal attributes
    storeLe<uint32_t>(central, 0);  // external attributes
    storeLe<uint32_t>(central, offset);
    central += name;
  }
  const uint32_t cdOffset = static_cast<uint32_t>(zip.size());
  zip += central;
  storeLe<uint32_t>(zip, kEndSig);
  storeLe<uint16_t>(zip, 0);
  storeLe<uint16_t>(zip, 0);
  storeLe<uint16_t>(zip, static_cast<uint16_t>(entries.size()));
  storeLe<uint16_t>(zip, static_cast<uint16_t>(entries.size()));
  storeLe<uint32_t>(zip, static_cast<uint32_t>(central.size()));
  storeLe<uint32_t>(zip, cdOffset);
  storeLe<uint16_t>(zip, 0);
  // Written beside the target and renamed, so a failure never leaves a half-written file.
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw IoError("cannot write '" + path.string() + "'");
    out.write(zip.data(), static_cast<std::streamsize>(zip.size()));
    if (!out) throw IoError("failed writing '" + path.string() + "'");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw IoError("cannot write '" + path.string() + "': " + ec.message());
  }
}

}  // namespace s2p
