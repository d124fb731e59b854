// The Python bindings of Plane<T>: the class (float64 as Plane, float32 as Plane32) and its
// queries.
#include "bind.hpp"

namespace rayproof::python {

template <class T> void bind_plane(py::module_& m) {
    auto c = shape_class<T, Plane<T>>(m, "Plane", "The surface of the points p with normal.p == offset.");
    c.def(py::init([](const py::object& normal, const py::object& offset) {
              return Plane<T>{vec3<T>(normal, "normal"), scalar<T>(offset, "offset")};
          }),
          py::arg("normal"), py::arg("offset"));
    vec3_property(c, "normal", &Plane<T>::normal);
    scalar_property(c, "offset", &Plane<T>::offset);
    bind_queries<T, Plane<T>>(m);
}

template void bind_plane<float>(py::module_&);
template void bind_plane<double>(py::module_&);

}  // namespace rayproof::python
