// The pieces every shape's bindings share: the run-time mode, its dispatch to the
// kernel's mode tags, and the query functions (scalar and NumPy batch) for one shape.
#pragma once

#include <rayproof/rayproof.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

namespace rayproof::python {

namespace py = pybind11;

// The mode chosen at run time from Python: the kernel's RuntimeMode, dispatched to the
// kernel's tags by rayproof::with_mode (a value outside the three answers as certified).
using Mode = ::rayproof::RuntimeMode;

template <class F> decltype(auto) with_mode(Mode mode, F&& f) {
    return ::rayproof::with_mode(mode, f, [&] { return f(rayproof::certified); });
}

// The Python names of the scalar types: Ray (double), Ray32 (float).
template <class T> std::string type_name(const char* stem) {
    return std::string(stem) + (std::is_same_v<T, float> ? "32" : "");
}

// Input numbers. Python numbers and lists are rounded once to T; a NumPy float of the
// other width is refused (TypeError) rather than rounded silently, so that a float32
// query runs on float32 numbers exactly as given and a float64 one never on float32
// data by accident.
template <class T> void refuse_other_width(py::handle h, const char* what) {
    // NumPy arrays and NumPy scalars only (other objects with a dtype are converted).
    const bool array = py::isinstance<py::array>(h);
    if (!array && !py::isinstance(h, py::module_::import("numpy").attr("generic"))) return;
    const py::dtype dt = array ? py::reinterpret_borrow<py::array>(h).dtype()
                               : py::reinterpret_borrow<py::object>(h).attr("dtype").cast<py::dtype>();
    if (dt.kind() == 'f' && dt.itemsize() != static_cast<py::ssize_t>(sizeof(T)))
        throw py::type_error(std::string(what) + " is float" + std::to_string(8 * dt.itemsize()) + " but this is a float" +
                             std::to_string(8 * sizeof(T)) + " type: convert it explicitly");
}

template <class T> T scalar(py::handle h, const char* what) {
    refuse_other_width<T>(h, what);
    return static_cast<T>(py::float_(py::reinterpret_borrow<py::object>(h)).cast<double>());
}

template <class T> py::array_t<T, py::array::forcecast | py::array::c_style> numbers(py::handle h, const char* what,
                                                                                    py::ssize_t size) {
    refuse_other_width<T>(h, what);
    auto a = py::array_t<T, py::array::forcecast | py::array::c_style>::ensure(h);
    if (!a || a.size() != size)
        throw py::type_error(std::string(what) + ": expected " + std::to_string(size) + " numbers");
    return a;
}

template <class T> Vec3<T> vec3(py::handle h, const char* what) {
    const auto a = numbers<T>(h, what, 3);
    return Vec3<T>(a.data()[0], a.data()[1], a.data()[2]);
}

// A 3x3 matrix given as rows: m[i][j] (NumPy's a[i, j]) is entry (i, j).
template <class T> Mat3<T> mat3(py::handle h, const char* what) {
    const auto a = numbers<T>(h, what, 9);
    if (a.ndim() != 2) throw py::type_error(std::string(what) + ": expected a 3x3 matrix");
    Mat3<T> m;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m(i, j) = a.data()[3 * i + j];
    return m;
}

template <class T> py::array_t<T> to_array(const Vec3<T>& v) {
    py::array_t<T> a(3);
    for (int i = 0; i < 3; ++i) a.mutable_data()[i] = v[i];
    return a;
}
template <class T> py::array_t<T> to_array(const Mat3<T>& m) {
    py::array_t<T> a({py::ssize_t(3), py::ssize_t(3)});
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) a.mutable_data()[3 * i + j] = m(i, j);
    return a;
}

// A read-write attribute of a value type: NumPy copies out, the rules above in.
template <class C, class T> void vec3_property(py::class_<C>& c, const char* name, Vec3<T> C::*member) {
    c.def_property(
        name, [member](const C& x) { return to_array<T>(x.*member); },
        [member, name](C& x, const py::object& v) { x.*member = vec3<T>(v, name); });
}
template <class C, class T> void mat3_property(py::class_<C>& c, const char* name, Mat3<T> C::*member) {
    c.def_property(
        name, [member](const C& x) { return to_array<T>(x.*member); },
        [member, name](C& x, const py::object& v) { x.*member = mat3<T>(v, name); });
}
template <class C, class T> void scalar_property(py::class_<C>& c, const char* name, T C::*member) {
    c.def_property(
        name, [member](const C& x) { return x.*member; },
        [member, name](C& x, const py::object& v) { x.*member = scalar<T>(v, name); });
}

template <class X> std::string repr(const X& x) {
    std::ostringstream os;
    os << x;
    return os.str();
}

// Rays are copied out of the NumPy arrays in chunks of this many (a bounded buffer for
// the kernel's span forms, whatever the array's strides and alignment).
inline constexpr std::size_t kChunk = 4096;

// Checks the shapes of the arrays the Python layer has already broadcast.
inline std::size_t batch_size(const py::array& origins, const py::array& directions, const py::array& t_min,
                              const py::array& t_max) {
    if (origins.ndim() != 2 || origins.shape(1) != 3 || directions.ndim() != 2 || directions.shape(1) != 3)
        throw py::value_error("origins and directions must have shape (N, 3)");
    const auto n = origins.shape(0);
    if (directions.shape(0) != n || t_min.ndim() != 1 || t_max.ndim() != 1 || t_min.shape(0) != n ||
        t_max.shape(0) != n)
        throw py::value_error("origins, directions, t_min and t_max must have the same length N");
    return static_cast<std::size_t>(n);
}

// Runs `per_chunk(rays)` on consecutive chunks of the rays described by the arrays, the
// GIL released while the kernel runs. The arrays are of T already (no conversion: the
// Python layer refuses a float array of the other width rather than round it).
template <class T, class PerChunk>
void for_each_chunk(const py::array_t<T>& origins, const py::array_t<T>& directions, const py::array_t<T>& t_min,
                    const py::array_t<T>& t_max, PerChunk&& per_chunk) {
    const std::size_t n = batch_size(origins, directions, t_min, t_max);
    const auto o = origins.template unchecked<2>();
    const auto d = directions.template unchecked<2>();
    const auto lo = t_min.template unchecked<1>();
    const auto hi = t_max.template unchecked<1>();
    std::vector<Ray<T>> rays(std::min(n, kChunk));
    for (std::size_t start = 0; start < n; start += kChunk) {
        const std::size_t count = std::min(kChunk, n - start);
        for (std::size_t k = 0; k < count; ++k) {
            const auto i = static_cast<py::ssize_t>(start + k);
            Ray<T>& r = rays[k];
            r.origin = Vec3<T>(o(i, 0), o(i, 1), o(i, 2));
            r.direction = Vec3<T>(d(i, 0), d(i, 1), d(i, 2));
            r.t_min = lo(i);
            r.t_max = hi(i);
        }
        per_chunk(start, std::span<const Ray<T>>(rays.data(), count));
    }
}

// intersect, verdict and normal for one shape type, scalar and batch.
template <class T, class Shape> void bind_queries(py::module_& m) {
    m.def(
        "intersect",
        [](const Ray<T>& ray, const Shape& shape, Mode mode) {
            return with_mode(mode, [&](auto tag) { return rayproof::intersect(ray, shape, tag); });
        },
        py::arg("ray"), py::arg("shape"), py::arg("mode"));
    m.def(
        "verdict",
        [](const Ray<T>& ray, const Shape& shape, Mode mode) {
            return with_mode(mode, [&](auto tag) { return rayproof::verdict(ray, shape, tag); });
        },
        py::arg("ray"), py::arg("shape"), py::arg("mode"));
    m.def(
        "normal",
        [](const Shape& shape, const Hit<T>& hit, const Ray<T>& ray) { return to_array<T>(rayproof::normal(shape, hit, ray)); },
        py::arg("shape"), py::arg("hit"), py::arg("ray"));

    // The batch forms: (N, 3) origins and directions, (N,) t_min and t_max, all of T,
    // in; separate arrays out (verdict codes as int8, t_enter, t_exit of T, face as
    // int32). Each chunk goes through the kernel's span form.
    m.def(
        "_intersect_batch",
        [](const py::array_t<T>& origins, const py::array_t<T>& directions, const py::array_t<T>& t_min,
           const py::array_t<T>& t_max, const Shape& shape, Mode mode) {
            const std::size_t n = batch_size(origins, directions, t_min, t_max);
            const auto size = static_cast<py::ssize_t>(n);
            py::array_t<std::int8_t> verdicts(size);
            py::array_t<T> t_enter(size), t_exit(size);
            py::array_t<std::int32_t> faces(size);
            auto v = verdicts.template mutable_unchecked<1>();
            auto te = t_enter.template mutable_unchecked<1>();
            auto tx = t_exit.template mutable_unchecked<1>();
            auto f = faces.template mutable_unchecked<1>();
            std::vector<Hit<T>> hits(std::min(n, kChunk));
            for_each_chunk<T>(origins, directions, t_min, t_max, [&](std::size_t start, std::span<const Ray<T>> rays) {
                const std::span<Hit<T>> out(hits.data(), rays.size());
                {
                    py::gil_scoped_release unlocked;
                    with_mode(mode, [&](auto tag) { rayproof::intersect(rays, shape, tag, out); });
                }
                for (std::size_t k = 0; k < rays.size(); ++k) {
                    const auto i = static_cast<py::ssize_t>(start + k);
                    v(i) = static_cast<std::int8_t>(out[k].verdict);
                    te(i) = out[k].t_enter;
                    tx(i) = out[k].t_exit;
                    f(i) = out[k].face;
                }
            });
            return py::make_tuple(verdicts, t_enter, t_exit, faces);
        },
        py::arg("origins").noconvert(), py::arg("directions").noconvert(), py::arg("t_min").noconvert(),
        py::arg("t_max").noconvert(), py::arg("shape"), py::arg("mode"));
    m.def(
        "_verdict_batch",
        [](const py::array_t<T>& origins, const py::array_t<T>& directions, const py::array_t<T>& t_min,
           const py::array_t<T>& t_max, const Shape& shape, Mode mode) {
            const std::size_t n = batch_size(origins, directions, t_min, t_max);
            py::array_t<std::int8_t> verdicts(static_cast<py::ssize_t>(n));
            auto v = verdicts.template mutable_unchecked<1>();
            std::vector<Verdict> answers(std::min(n, kChunk));
            for_each_chunk<T>(origins, directions, t_min, t_max, [&](std::size_t start, std::span<const Ray<T>> rays) {
                const std::span<Verdict> out(answers.data(), rays.size());
                {
                    py::gil_scoped_release unlocked;
                    with_mode(mode, [&](auto tag) { rayproof::verdict(rays, shape, tag, out); });
                }
                for (std::size_t k = 0; k < rays.size(); ++k)
                    v(static_cast<py::ssize_t>(start + k)) = static_cast<std::int8_t>(out[k]);
            });
            return verdicts;
        },
        py::arg("origins").noconvert(), py::arg("directions").noconvert(), py::arg("t_min").noconvert(),
        py::arg("t_max").noconvert(), py::arg("shape"), py::arg("mode"));
}

// The class of one shape, with a hexadecimal repr and its queries.
template <class T, class Shape> py::class_<Shape> shape_class(py::module_& m, const char* stem, const char* doc) {
    py::class_<Shape> c(m, type_name<T>(stem).c_str(), doc);
    c.def("__repr__", [](const Shape& s) { return repr(s); });
    c.def_property_readonly_static("dtype", [](const py::object&) { return py::dtype::of<T>(); });
    return c;
}

template <class T> void bind_aabb(py::module_& m);
template <class T> void bind_obb(py::module_& m);
template <class T> void bind_plane(py::module_& m);
template <class T> void bind_sphere(py::module_& m);

}  // namespace rayproof::python
