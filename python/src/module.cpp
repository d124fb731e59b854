// rayproof._rayproof — the pybind11 extension module under the rayproof package: the
// value types in float64 (Ray, Aabb, ..., Hit) and float32 (Ray32, Aabb32, ..., Hit32),
// the verdict and the run-time mode, and every query of the kernel, scalar and batch.
// The Python package (rayproof/__init__.py) adds the NumPy batch interface on top.
#include "bind.hpp"

#include <limits>

namespace rayproof::python {
namespace {

template <class T> void bind_types(py::module_& m) {
    py::class_<Ray<T>> ray(m, type_name<T>("Ray").c_str(), "The ray o + t*d for real t in [t_min, t_max].");
    ray.def(py::init([](const py::object& origin, const py::object& direction, const py::object& t_min,
                        const py::object& t_max) {
                return Ray<T>{vec3<T>(origin, "origin"), vec3<T>(direction, "direction"), scalar<T>(t_min, "t_min"),
                              scalar<T>(t_max, "t_max")};
            }),
            py::arg("origin"), py::arg("direction"), py::arg("t_min") = py::float_(0.0),
            py::arg("t_max") = py::float_(std::numeric_limits<double>::infinity()));
    vec3_property(ray, "origin", &Ray<T>::origin);
    vec3_property(ray, "direction", &Ray<T>::direction);
    scalar_property(ray, "t_min", &Ray<T>::t_min);
    scalar_property(ray, "t_max", &Ray<T>::t_max);
    ray.def_property_readonly_static("dtype", [](const py::object&) { return py::dtype::of<T>(); });
    ray.def("__repr__", [](const Ray<T>& r) { return repr(r); });

    py::class_<Hit<T>>(m, type_name<T>("Hit").c_str(),
                       "An answer: the verdict, [t_enter, t_exit] when it is a hit, and the entry face of a box.")
        .def(py::init([](Verdict verdict, T t_enter, T t_exit, int face) { return Hit<T>{verdict, t_enter, t_exit, face}; }),
             py::arg("verdict") = Verdict::miss, py::arg("t_enter") = T(0), py::arg("t_exit") = T(0),
             py::arg("face") = -1)
        .def_readwrite("verdict", &Hit<T>::verdict)
        .def_readwrite("t_enter", &Hit<T>::t_enter)
        .def_readwrite("t_exit", &Hit<T>::t_exit)
        .def_readwrite("face", &Hit<T>::face)
        .def("__bool__", [](const Hit<T>& h) { return static_cast<bool>(h); })
        .def("__eq__",
             [](const Hit<T>& a, const Hit<T>& b) {
                 return a.verdict == b.verdict && a.t_enter == b.t_enter && a.t_exit == b.t_exit && a.face == b.face;
             })
        .def_property_readonly_static("dtype", [](const py::object&) { return py::dtype::of<T>(); })
        .def("__repr__", [](const Hit<T>& h) { return repr(h); });

    m.def("reversed", &rayproof::reversed<T>, py::arg("ray"),
          "The same ray traversed backwards: its interval is [-t_exit, -t_enter] of the original.");
}

}  // namespace
}  // namespace rayproof::python

PYBIND11_MODULE(_rayproof, m) {
    namespace rp = rayproof::python;
    m.doc() = "rayproof's kernel: ray against Aabb, Obb, Plane and Sphere in three modes, float32 and float64.";

    pybind11::enum_<rayproof::Verdict>(m, "Verdict", "The answer's verdict (int values: miss 0, hit 1, invalid 2).")
        .value("miss", rayproof::Verdict::miss)
        .value("hit", rayproof::Verdict::hit)
        .value("invalid", rayproof::Verdict::invalid);
    pybind11::enum_<rp::Mode>(m, "Mode",
                              "fast: plain floating point, no promise; conservative: never misses an exact hit, "
                              "its interval encloses the exact one; certified: verdict and face exact, t faithful.")
        .value("fast", rp::Mode::fast)
        .value("conservative", rp::Mode::conservative)
        .value("certified", rp::Mode::certified)
        .export_values();

    rp::bind_types<double>(m);
    rp::bind_types<float>(m);
    rp::bind_aabb<double>(m);
    rp::bind_aabb<float>(m);
    rp::bind_obb<double>(m);
    rp::bind_obb<float>(m);
    rp::bind_plane<double>(m);
    rp::bind_plane<float>(m);
    rp::bind_sphere<double>(m);
    rp::bind_sphere<float>(m);
}
