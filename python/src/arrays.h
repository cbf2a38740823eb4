#pragma once
// numpy <-> simdbvh conversions for the Python module: N x 3 point arrays,
// rays from origins and directions, and output arrays. Inputs are converted to
// float32 (a copy when the dtype or layout requires it, as the docstrings say).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "simdbvh/kernels/error.h"
#include "simdbvh/kernels/ray.h"

namespace simdbvh::python {

namespace py = pybind11;
using F32 = py::array_t<float, py::array::c_style | py::array::forcecast>;

// A C-contiguous float32 (n, 3) array (forcecast copies other dtypes and layouts).
inline F32 as_points(const py::handle& obj, const char* what) {
    F32 a = F32::ensure(obj);
    if (!a) throw Error(std::string(what) + ": expected an array of numbers");
    if (a.ndim() == 1 && a.shape(0) == 3) a = a.reshape({py::ssize_t(1), py::ssize_t(3)});
    if (a.ndim() != 2 || a.shape(1) != 3) {
        std::string shape;
        for (py::ssize_t k = 0; k < a.ndim(); ++k) shape += (k ? ", " : "") + std::to_string(a.shape(k));
        throw Error(std::string(what) + ": expected shape (n, 3), got (" + shape + ")");
    }
    return a;
}

inline const Vec3* vec3s(const F32& a) { return reinterpret_cast<const Vec3*>(a.data()); }

// One float per ray: a scalar, or an array of n.
inline std::vector<float> per_ray(const py::handle& obj, std::size_t n, const char* what) {
    F32 a = F32::ensure(obj);
    if (!a) throw Error(std::string(what) + ": expected a number or an array of numbers");
    if (a.ndim() == 0) return std::vector<float>(n, a.data()[0]);
    if (a.ndim() != 1 || std::size_t(a.shape(0)) != n)
        throw Error(std::string(what) + ": expected a number or shape (" + std::to_string(n) + ",)");
    return std::vector<float>(a.data(), a.data() + n);
}

inline std::vector<Ray> make_rays(const py::handle& origins, const py::handle& directions, const py::handle& tmin,
                                  const py::handle& tmax) {
    const F32 o = as_points(origins, "origins"), d = as_points(directions, "directions");
    if (o.shape(0) != d.shape(0))
        throw Error("origins and directions differ in length (" + std::to_string(o.shape(0)) + " and " +
                    std::to_string(d.shape(0)) + ")");
    const auto n = std::size_t(o.shape(0));
    const auto lo = per_ray(tmin, n, "tmin"), hi = per_ray(tmax, n, "tmax");
    std::vector<Ray> rays(n);
    for (std::size_t i = 0; i < n; ++i) rays[i] = Ray{vec3s(o)[i], lo[i], vec3s(d)[i], hi[i]};
    return rays;
}

template <class T>
py::array_t<T> empty_array(std::size_t n) {
    return py::array_t<T>(py::ssize_t(n));
}

inline py::array_t<float> empty_points(std::size_t n) {
    return py::array_t<float>({py::ssize_t(n), py::ssize_t(3)});
}

}  // namespace simdbvh::python
