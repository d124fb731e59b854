// The Python bindings of Sphere<T>: the class (float64 as Sphere, float32 as Sphere32) and its
// queries.
#include "bind.hpp"

namespace rayproof::python {

template <class T> void bind_sphere(py::module_& m) {
    auto c = shape_class<T, Sphere<T>>(m, "Sphere", "The closed ball |p - center| <= radius (radius 0 is a point).");
    c.def(py::init([](const py::object& center, const py::object& radius) {
              return Sphere<T>{vec3<T>(center, "center"), scalar<T>(radius, "radius")};
          }),
          py::arg("center"), py::arg("radius"));
    vec3_property(c, "center", &Sphere<T>::center);
    scalar_property(c, "radius", &Sphere<T>::radius);
    bind_queries<T, Sphere<T>>(m);
}

template void bind_sphere<float>(py::module_&);
template void bind_sphere<double>(py::module_&);

}  // namespace rayproof::python
