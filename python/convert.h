// NumPy arrays and Python values to Penumbra's types, each checked with a one-line message that
// names the argument (penumbra.Error, a ValueError): shape, dtype, finiteness, index range. No
// conversion trusts its input; none can crash on it.
//
// Thread-safety: needs the GIL (it touches Python objects).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/error.h"

namespace penumbra::python {

namespace py = pybind11;

// Raised to Python as penumbra.Error (registered by the module) with what() as the message.
struct PenumbraError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
[[noreturn]] void raise(const std::string& line);
[[noreturn]] inline void raise(const engine::Error& e) {
  raise(e.line());
}

// An N x cols array of numbers (any float or integer dtype, converted to float32), every value
// finite; N may be 0. `what` names the argument in errors ("vertices").
std::vector<float> floatRows(py::handle a, int cols, const std::string& what);
std::vector<glm::vec2> vec2Rows(py::handle a, const std::string& what);
std::vector<glm::vec3> vec3Rows(py::handle a, const std::string& what);
std::vector<glm::vec4> vec4Rows(py::handle a, const std::string& what);
// An M x 3 array of integers (int or uint dtype; floats are refused, not truncated), each in
// [0, vertexCount): 3 per triangle.
std::vector<uint32_t> triangleRows(py::handle a, size_t vertexCount, const std::string& what);
// A 4 x 4 matrix as NumPy writes one (rows; M @ [x, y, z, 1]), finite, to GLM's columns.
glm::mat4 matrix4(py::handle a, const std::string& what);
// n finite numbers (a tuple, list or array).
glm::vec3 vec3Value(py::handle a, const std::string& what);
glm::vec4 colorValue(py::handle a, const std::string& what);  // RGB or RGBA, alpha 1 when RGB

// A C-contiguous NumPy array of shape `shape` owning a copy of `data`.
template <class T>
py::array_t<T> toArray(const std::vector<T>& data, std::vector<py::ssize_t> shape) {
  py::array_t<T> out(shape);
  std::copy(data.begin(), data.end(), out.mutable_data());
  return out;
}

}  // namespace penumbra::python
