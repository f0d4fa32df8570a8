#include "convert.h"

#include <cmath>
#include <limits>

namespace penumbra::python {

void raise(const std::string& line) {
  throw PenumbraError(line);
}

namespace {

std::string shapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

py::array asArray(py::handle h, const std::string& what) {
  if (h.is_none()) raise(what + ": expected an array, got None");
  py::array a;
  try {
    a = py::array::ensure(h);
  } catch (const py::error_already_set&) {
  }
  if (!a) raise(what + ": expected an array of numbers");
  return a;
}

void requireRows(const py::array& a, py::ssize_t cols, const std::string& what) {
  if (a.ndim() != 2 || a.shape(1) != cols)
    raise(what + ": expected shape (N, " + std::to_string(cols) + "), got " + shapeText(a));
  if (static_cast<uint64_t>(a.shape(0)) >= (uint64_t{1} << 32))
    raise(what + ": " + std::to_string(a.shape(0)) + " rows, more than 2^32 - 1");
}

template <class V, int N>
std::vector<V> rowsOf(py::handle h, const std::string& what) {
  const std::vector<float> f = floatRows(h, N, what);
  std::vector<V> out(f.size() / N);
  for (size_t i = 0; i < out.size(); ++i)
    for (int k = 0; k < N; ++k) out[i][k] = f[i * N + static_cast<size_t>(k)];
  return out;
}

}  // namespace

std::vector<float> floatRows(py::handle h, int cols, const std::string& what) {
  const py::array a = asArray(h, what);
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    raise(what + ": expected numbers, got dtype " + std::string(py::str(a.dtype())));
  requireRows(a, cols, what);
  const auto f = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!f) raise(what + ": cannot be read as float32");
  std::vector<float> out(f.data(), f.data() + f.size());
  for (size_t i = 0; i < out.size(); ++i)
    if (!std::isfinite(out[i]))
      raise(what + ": row " + std::to_string(i / static_cast<size_t>(cols)) + " is not finite (" +
            std::to_string(out[i]) + ")");
  return out;
}

std::vector<glm::vec2> vec2Rows(py::handle a, const std::string& what) {
  return rowsOf<glm::vec2, 2>(a, what);
}
std::vector<glm::vec3> vec3Rows(py::handle a, const std::string& what) {
  return rowsOf<glm::vec3, 3>(a, what);
}
std::vector<glm::vec4> vec4Rows(py::handle a, const std::string& what) {
  return rowsOf<glm::vec4, 4>(a, what);
}

std::vector<uint32_t> triangleRows(py::handle h, size_t vertexCount, const std::string& what) {
  const py::array a = asArray(h, what);
  const char kind = a.dtype().kind();
  if (kind != 'i' && kind != 'u')
    raise(what + ": expected integer indices (int32 or uint32), got dtype " +
          std::string(py::str(a.dtype())));
  requireRows(a, 3, what);
  // Through int64 (uint64 beyond its range wraps negative and is refused like any negative).
  const auto i64 = py::array_t<int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!i64) raise(what + ": cannot be read as integers");
  std::vector<uint32_t> out(static_cast<size_t>(i64.size()));
  const int64_t* d = i64.data();
  for (size_t i = 0; i < out.size(); ++i) {
    if (d[i] < 0 || static_cast<uint64_t>(d[i]) >= vertexCount)
      raise(what + ": triangle " + std::to_string(i / 3) + " has index " + std::to_string(d[i]) +
            ", out of range (" + std::to_string(vertexCount) + " vertices)");
    out[i] = static_cast<uint32_t>(d[i]);
  }
  return out;
}

glm::mat4 matrix4(py::handle h, const std::string& what) {
  const py::array a = asArray(h, what);
  if (a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
    raise(what + ": expected shape (4, 4), got " + shapeText(a));
  const std::vector<float> f = floatRows(a, 4, what);
  glm::mat4 m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = f[static_cast<size_t>(r * 4 + c)];
  return m;
}

glm::vec3 vec3Value(py::handle h, const std::string& what) {
  py::array a = asArray(h, what);
  if (a.size() != 3 || a.ndim() != 1) raise(what + ": expected 3 numbers, got shape " + shapeText(a));
  const std::vector<float> f = floatRows(a.reshape(std::vector<py::ssize_t>{1, 3}), 3, what);
  return {f[0], f[1], f[2]};
}

glm::vec4 colorValue(py::handle h, const std::string& what) {
  py::array a = asArray(h, what);
  if (a.ndim() != 1 || (a.size() != 3 && a.size() != 4))
    raise(what + ": expected 3 or 4 numbers (RGB or RGBA), got shape " + shapeText(a));
  const py::ssize_t n = a.size();
  const std::vector<float> f =
      floatRows(a.reshape(std::vector<py::ssize_t>{1, n}), static_cast<int>(n), what);
  return {f[0], f[1], f[2], n == 4 ? f[3] : 1.0f};
}

}  // namespace penumbra::python
