// The Python binding of VisiLibity1's visibility polygon: two functions over flat arrays.
//
//   visibility_polygon(vertices, counts, x, y, epsilon) -> bytes
//   environment_is_valid(vertices, counts, epsilon) -> bool
//
// vertices: float64 (x, y) pairs of the environment's polygons, the outer boundary first (counter-clockwise),
// then the holes (clockwise), back to back; counts: int64, the number of vertices of each polygon; (x, y): the
// observer, in the vertices' frame; epsilon: VisiLibity's snapping distance. Both arrays are read through the
// buffer protocol (numpy arrays, bytes), C-contiguous. Returns the visibility polygon's vertices as float64
// (x, y) pairs, counter-clockwise, in the same frame (numpy.frombuffer(...).reshape(-1, 2)).
//
// environment_is_valid is VisiLibity's Environment::is_valid: the precondition of the sweep. The sweep runs without
// the GIL. Arrays whose lengths or counts do not fit raise ValueError; anything the C++ side throws, RuntimeError.
// The buffers' element types are not checked (a buffer is read as raw bytes): the Python side (conversion.py)
// always hands over C-contiguous, aligned float64 and int64 numpy arrays.
// This file is part of omega-prime-visibility (MPL-2.0); visilibity.cpp and visilibity.hpp are VisiLibity1
// 1.0.10 by Karl J. Obermeyer (LGPL-3.0-or-later, see COPYING.LESSER).

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <cstdint>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "visilibity.hpp"

namespace {

// The buffers a call holds, released on every path out.
struct Buffers {
    Py_buffer vertices{};
    Py_buffer counts{};
    ~Buffers() {
        if (vertices.obj) PyBuffer_Release(&vertices);
        if (counts.obj) PyBuffer_Release(&counts);
    }
};

// The environment's polygons from the flat arrays, or an error message.
const char* build_polygons(const double* xy, Py_ssize_t n_points, const int64_t* counts, Py_ssize_t n_polygons,
                           std::vector<VisiLibity::Polygon>& polygons) {
    if (n_polygons < 1) return "the environment needs an outer boundary (counts is empty)";
    Py_ssize_t k = 0;
    for (Py_ssize_t p = 0; p < n_polygons; p++) {
        if (counts[p] < 3) return "every polygon needs at least 3 vertices";
        if (counts[p] > n_points - k) return "counts add up to more vertices than given";
        std::vector<VisiLibity::Point> points;
        points.reserve(static_cast<size_t>(counts[p]));
        for (int64_t i = 0; i < counts[p]; i++, k++) points.emplace_back(xy[2 * k], xy[2 * k + 1]);
        polygons.emplace_back(points);
    }
    if (k != n_points) return "counts add up to fewer vertices than given";
    return nullptr;
}

// Reads the two arrays of a call; false (with the Python error set) if they are malformed.
bool read_arrays(Buffers& held, Py_ssize_t& n_points, Py_ssize_t& n_polygons) {
    if (held.vertices.len % (2 * sizeof(double)) || held.counts.len % sizeof(int64_t)) {
        PyErr_SetString(PyExc_ValueError, "vertices must be float64 (x, y) pairs and counts int64");
        return false;
    }
    n_points = held.vertices.len / static_cast<Py_ssize_t>(2 * sizeof(double));
    n_polygons = held.counts.len / static_cast<Py_ssize_t>(sizeof(int64_t));
    return true;
}

// Runs `work` on the environment without the GIL; false (with the Python error set) if the arrays do not describe
// polygons or the C++ side throws.
template <typename Work>
bool with_environment(Buffers& held, Py_ssize_t n_points, Py_ssize_t n_polygons, Work work) {
    const char* problem = nullptr;
    bool failed = false;
    std::string what;
    Py_BEGIN_ALLOW_THREADS
    try {
        std::vector<VisiLibity::Polygon> polygons;
        problem = build_polygons(static_cast<const double*>(held.vertices.buf), n_points,
                                 static_cast<const int64_t*>(held.counts.buf), n_polygons, polygons);
        if (!problem) work(VisiLibity::Environment(polygons));
    } catch (const std::exception& error) {
        failed = true;
        what = error.what();
    } catch (...) {
        failed = true;
        what = "unknown C++ exception";
    }
    Py_END_ALLOW_THREADS
    if (problem) {
        PyErr_SetString(PyExc_ValueError, problem);
        return false;
    }
    if (failed) {
        PyErr_Format(PyExc_RuntimeError, "VisiLibity failed: %s", what.c_str());
        return false;
    }
    return true;
}

PyObject* visibility_polygon(PyObject*, PyObject* args) {
    Buffers held;
    double x, y, epsilon;
    Py_ssize_t n_points, n_polygons;
    if (!PyArg_ParseTuple(args, "y*y*ddd:visibility_polygon", &held.vertices, &held.counts, &x, &y, &epsilon) ||
        !read_arrays(held, n_points, n_polygons))
        return nullptr;
    std::vector<double> out;
    auto sweep = [&](const VisiLibity::Environment& environment) {
        VisiLibity::Visibility_Polygon polygon(VisiLibity::Point(x, y), environment, epsilon);
        const unsigned n = polygon.n();
        out.resize(2 * static_cast<size_t>(n));
        for (unsigned i = 0; i < n; i++) {
            out[2 * i] = polygon[i].x();
            out[2 * i + 1] = polygon[i].y();
        }
    };
    if (!with_environment(held, n_points, n_polygons, sweep)) return nullptr;
    return PyBytes_FromStringAndSize(reinterpret_cast<const char*>(out.data()),
                                     static_cast<Py_ssize_t>(out.size() * sizeof(double)));
}

PyObject* environment_is_valid(PyObject*, PyObject* args) {
    Buffers held;
    double epsilon;
    Py_ssize_t n_points, n_polygons;
    if (!PyArg_ParseTuple(args, "y*y*d:environment_is_valid", &held.vertices, &held.counts, &epsilon) ||
        !read_arrays(held, n_points, n_polygons))
        return nullptr;
    bool valid = false;
    auto check = [&](const VisiLibity::Environment& environment) { valid = environment.is_valid(epsilon); };
    if (!with_environment(held, n_points, n_polygons, check)) return nullptr;
    return PyBool_FromLong(valid);
}

PyMethodDef methods[] = {
    {"visibility_polygon", visibility_polygon, METH_VARARGS,
     "visibility_polygon(vertices, counts, x, y, epsilon) -> bytes\n\n"
     "VisiLibity1's visibility polygon from (x, y) in the environment of the polygons given by float64 (x, y)\n"
     "pairs `vertices` and int64 vertex `counts` (outer boundary first, counter-clockwise; holes clockwise), as\n"
     "float64 (x, y) pairs, counter-clockwise."},
    {"environment_is_valid", environment_is_valid, METH_VARARGS,
     "environment_is_valid(vertices, counts, epsilon) -> bool\n\n"
     "VisiLibity1's Environment::is_valid(epsilon) of the polygons given as for visibility_polygon."},
    {nullptr, nullptr, 0, nullptr}};

PyModuleDef module = {PyModuleDef_HEAD_INIT, "_visilibity1",
                      "VisiLibity1's visibility polygon over flat arrays (see binding.cpp).", -1, methods};

}  // namespace

PyMODINIT_FUNC PyInit__visilibity1(void) { return PyModule_Create(&module); }
