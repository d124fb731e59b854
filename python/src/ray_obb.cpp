// The Python bindings of Obb<T>: the class (float64 as Obb, float32 as Obb32) and its
// queries.
#include "bind.hpp"

namespace rayproof::python {

template <class T> void bind_obb(py::module_& m) {
    auto c = shape_class<T, Obb<T>>(m, "Obb",
                                    "The closed solid |(p - center).a_i| <= half_extent_i, a_i = axes[:, i] (a column) "
                                    "exactly as stored.");
    c.def(py::init([](const py::object& center, const py::object& axes, const py::object& half_extent) {
              return Obb<T>{vec3<T>(center, "center"), mat3<T>(axes, "axes"), vec3<T>(half_extent, "half_extent")};
          }),
          py::arg("center"), py::arg("axes"), py::arg("half_extent"));
    vec3_property(c, "center", &Obb<T>::center);
    mat3_property(c, "axes", &Obb<T>::axes);
    vec3_property(c, "half_extent", &Obb<T>::half_extent);
    bind_queries<T, Obb<T>>(m);
}

template void bind_obb<float>(py::module_&);
template void bind_obb<double>(py::module_&);

}  // namespace rayproof::python
