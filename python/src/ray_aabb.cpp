// The Python bindings of Aabb<T>: the class (float64 as Aabb, float32 as Aabb32) and its
// queries.
#include "bind.hpp"

namespace rayproof::python {

template <class T> void bind_aabb(py::module_& m) {
    auto c = shape_class<T, Aabb<T>>(m, "Aabb", "The closed box lo <= p <= hi (lo == hi on an axis is a flat box).");
    c.def(py::init([](const py::object& lo, const py::object& hi) { return Aabb<T>{vec3<T>(lo, "lo"), vec3<T>(hi, "hi")}; }),
          py::arg("lo"), py::arg("hi"));
    vec3_property(c, "lo", &Aabb<T>::lo);
    vec3_property(c, "hi", &Aabb<T>::hi);
    bind_queries<T, Aabb<T>>(m);
}

template void bind_aabb<float>(py::module_&);
template void bind_aabb<double>(py::module_&);

}  // namespace rayproof::python
