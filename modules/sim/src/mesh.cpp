#include <superloc/sim/mesh.h>

#include <cmath>

namespace superloc::sim {

void Mesh::addTriangle(const Vec3d& a, const Vec3d& b, const Vec3d& c, float refl) {
    const int base = static_cast<int>(vertices.size());
    vertices.push_back(a.cast<float>());
    vertices.push_back(b.cast<float>());
    vertices.push_back(c.cast<float>());
    triangles.emplace_back(base, base + 1, base + 2);
    reflectivity.push_back(refl);
}

void Mesh::addQuad(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& d, float refl) {
    const int base = static_cast<int>(vertices.size());
    for (const Vec3d* p : {&a, &b, &c, &d}) vertices.push_back(p->cast<float>());
    triangles.emplace_back(base, base + 1, base + 2);
    triangles.emplace_back(base, base + 2, base + 3);
    reflectivity.push_back(refl);
    reflectivity.push_back(refl);
}

void Mesh::addGridQuad(const Vec3d& origin, const Vec3d& u, const Vec3d& v, int n_u, int n_v,
                       float refl) {
    n_u = std::max(1, n_u);
    n_v = std::max(1, n_v);
    const int base = static_cast<int>(vertices.size());
    for (int j = 0; j <= n_v; ++j)
        for (int i = 0; i <= n_u; ++i)
            vertices.push_back(
                (origin + u * (double(i) / n_u) + v * (double(j) / n_v)).cast<float>());
    const auto idx = [&](int i, int j) { return base + j * (n_u + 1) + i; };
    for (int j = 0; j < n_v; ++j)
        for (int i = 0; i < n_u; ++i) {
            triangles.emplace_back(idx(i, j), idx(i + 1, j), idx(i + 1, j + 1));
            triangles.emplace_back(idx(i, j), idx(i + 1, j + 1), idx(i, j + 1));
            reflectivity.push_back(refl);
            reflectivity.push_back(refl);
        }
}

void Mesh::addBox(const Vec3d& lo, const Vec3d& hi, float refl) {
    const Vec3d size = hi - lo;
    addOrientedBox(Vec3d(lo.x() + size.x() / 2, lo.y() + size.y() / 2, lo.z()), size, 0.0, refl);
}

void Mesh::addOrientedBox(const Vec3d& bc, const Vec3d& size, double yaw, float refl) {
    const double c = std::cos(yaw), s = std::sin(yaw);
    const auto corner = [&](double fx, double fy, double fz) {
        const double x = fx * size.x() / 2, y = fy * size.y() / 2;
        return Vec3d(bc.x() + c * x - s * y, bc.y() + s * x + c * y, bc.z() + fz * size.z());
    };
    const Vec3d p000 = corner(-1, -1, 0), p100 = corner(1, -1, 0), p110 = corner(1, 1, 0),
                p010 = corner(-1, 1, 0), p001 = corner(-1, -1, 1), p101 = corner(1, -1, 1),
                p111 = corner(1, 1, 1), p011 = corner(-1, 1, 1);
    addQuad(p000, p010, p110, p100, refl);  // bottom (normal -z)
    addQuad(p001, p101, p111, p011, refl);  // top
    addQuad(p000, p100, p101, p001, refl);  // -y side
    addQuad(p100, p110, p111, p101, refl);  // +x
    addQuad(p110, p010, p011, p111, refl);  // +y
    addQuad(p010, p000, p001, p011, refl);  // -x
}

void Mesh::addCylinder(const Vec3d& bc, double radius, double height, int segments, float refl) {
    segments = std::max(3, segments);
    const Vec3d top(bc.x(), bc.y(), bc.z() + height);
    for (int k = 0; k < segments; ++k) {
        const double a0 = 2 * M_PI * k / segments, a1 = 2 * M_PI * (k + 1) / segments;
        const Vec3d d0(radius * std::cos(a0), radius * std::sin(a0), 0);
        const Vec3d d1(radius * std::cos(a1), radius * std::sin(a1), 0);
        const Vec3d up(0, 0, height);
        addQuad(bc + d0, bc + d1, bc + d1 + up, bc + d0 + up, refl);
        addTriangle(top, top + d0, top + d1, refl);
    }
}

void Mesh::append(const Mesh& o) {
    const int base = static_cast<int>(vertices.size());
    vertices.insert(vertices.end(), o.vertices.begin(), o.vertices.end());
    for (const auto& t : o.triangles) triangles.emplace_back(t.array() + base);
    reflectivity.insert(reflectivity.end(), o.reflectivity.begin(), o.reflectivity.end());
}

Vec3d Mesh::normal(size_t i) const {
    const auto& t = triangles[i];
    const Vec3d a = vertices[t[0]].cast<double>(), b = vertices[t[1]].cast<double>(),
                c = vertices[t[2]].cast<double>();
    const Vec3d n = (b - a).cross(c - a);
    const double len = n.norm();
    return len > 0 ? Vec3d(n / len) : Vec3d::UnitZ();
}

double Mesh::area(size_t i) const {
    const auto& t = triangles[i];
    const Vec3d a = vertices[t[0]].cast<double>(), b = vertices[t[1]].cast<double>(),
                c = vertices[t[2]].cast<double>();
    return 0.5 * (b - a).cross(c - a).norm();
}

void Mesh::bounds(Vec3d& lo, Vec3d& hi) const {
    lo = Vec3d::Constant(1e300);
    hi = Vec3d::Constant(-1e300);
    for (const auto& v : vertices) {
        lo = lo.cwiseMin(v.cast<double>());
        hi = hi.cwiseMax(v.cast<double>());
    }
}

}  // namespace superloc::sim
