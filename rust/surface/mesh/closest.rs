//! Which triangle holds the closest point, and each triangle's unit normal: the mesh geometry
//! the Python layers ask for (closest face of a target, the outward normal a start flies out
//! along, the share of a reconstruction facing the wrong way), answered here once.

use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::query::{PointQuery, PointQueryWithLocation};
use parry3d_f64::shape::Triangle;

use super::{Surface, TriangleMesh};
use crate::error::Result;
use crate::geometry::{p, v, Point};

impl TriangleMesh {
    /// The surface point closest to `point` and the index of a triangle holding it (parry's
    /// projection with its location; on an edge or a vertex, one of the triangles sharing it).
    #[must_use]
    pub fn closest_face(&self, point: Point) -> (Point, usize) {
        let (projection, (face, _)) = self.mesh.project_local_point_and_get_location(v(point), false);
        (p(projection.point), face as usize)
    }

    /// The surface point closest to `point` and *every* triangle holding it, in increasing
    /// order: the one [`TriangleMesh::closest_face`] returns and, on an edge or a vertex, the
    /// others sharing it, and any other triangle through that point (two solids touching face
    /// to face, a pier's top under a deck). A triangle holds the point when it lies within a
    /// rounding tolerance of the nearest one: `1e-9` of the mesh's scale (its largest
    /// coordinate magnitude plus its largest extent, at least 1 m).
    #[must_use]
    pub fn faces_at_closest(&self, point: Point) -> (Point, Vec<usize>) {
        let closest = self.mesh.project_local_point(v(point), false).point;
        let aabb = self.mesh.local_aabb();
        let scale = aabb.mins.abs().max(aabb.maxs.abs()).max_element() + (aabb.maxs - aabb.mins).max_element();
        let tol = 1e-9 * scale.max(1.0);
        let query = Aabb::new(closest - tol, closest + tol);
        let mut found: Vec<(usize, f64)> = self
            .mesh
            .bvh()
            .intersect_aabb(&query)
            .map(|f| {
                let [a, b, c] = self.corners[f as usize];
                (f as usize, Triangle::new(a, b, c).distance_to_local_point(closest, false))
            })
            .collect();
        let least = found.iter().map(|&(_, d)| d).fold(f64::INFINITY, f64::min);
        found.retain(|&(_, d)| d <= least + tol);
        let mut faces: Vec<usize> = found.into_iter().map(|(f, _)| f).collect();
        faces.sort_unstable();
        (p(closest), faces)
    }

    /// The right-hand unit normal of each triangle (zero for a degenerate one).
    #[must_use]
    pub fn face_normals(&self) -> Vec<Point> {
        self.corners
            .iter()
            .map(|&[a, b, c]| {
                let n = (b - a).cross(c - a);
                let length = n.length();
                if length > 0.0 && length.is_finite() {
                    p(n / length)
                } else {
                    [0.0; 3]
                }
            })
            .collect()
    }
}

impl Surface {
    /// The closest surface point and a triangle holding it (see [`TriangleMesh::closest_face`]);
    /// a grid's triangles are numbered as its mesh path numbers them.
    ///
    /// # Errors
    /// As [`Surface::triangle_mesh`].
    pub fn closest_face(&self, point: Point) -> Result<(Point, usize)> {
        Ok(self.triangle_mesh()?.closest_face(point))
    }

    /// The closest surface point and every triangle holding it (see
    /// [`TriangleMesh::faces_at_closest`]).
    ///
    /// # Errors
    /// As [`Surface::triangle_mesh`].
    pub fn faces_at_closest(&self, point: Point) -> Result<(Point, Vec<usize>)> {
        Ok(self.triangle_mesh()?.faces_at_closest(point))
    }

    /// The right-hand unit normal of each triangle.
    ///
    /// # Errors
    /// As [`Surface::triangle_mesh`].
    pub fn face_normals(&self) -> Result<Vec<Point>> {
        Ok(self.triangle_mesh()?.face_normals())
    }
}

#[cfg(test)]
mod tests {
    use super::Surface;

    fn cube() -> Surface {
        let v = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [0.0, 1.0, 1.0],
            [1.0, 1.0, 1.0],
        ];
        let f = vec![
            [0, 2, 3],
            [0, 3, 1],
            [4, 5, 7],
            [4, 7, 6],
            [0, 1, 5],
            [0, 5, 4],
            [2, 6, 7],
            [2, 7, 3],
            [0, 4, 6],
            [0, 6, 2],
            [1, 3, 7],
            [1, 7, 5],
        ];
        Surface::new(v, f).unwrap()
    }

    #[test]
    fn the_closest_face_holds_the_closest_point_and_faces_the_query() {
        let s = cube();
        let normals = s.face_normals().unwrap();
        // Above the top, beside x = 1, below the bottom: the face's normal is the direction out.
        for (q, out) in [([0.3, 0.6, 4.0], [0.0, 0.0, 1.0]), ([3.0, 0.4, 0.7], [1.0, 0.0, 0.0]), ([0.2, 0.2, -2.0], [0.0, 0.0, -1.0])] {
            let (point, face) = s.closest_face(q).unwrap();
            assert_eq!(normals[face], out, "query {q:?} face {face}");
            let expected = q.map(|c| c.clamp(0.0, 1.0));
            assert!(point.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-12));
        }
    }

    #[test]
    fn normals_are_unit_and_outward_on_a_closed_cube() {
        let s = cube();
        for (face, n) in s.face_normals().unwrap().into_iter().enumerate() {
            let centre = s.triangle(face).iter().fold([0.0; 3], |acc, c| [acc[0] + c.x / 3.0, acc[1] + c.y / 3.0, acc[2] + c.z / 3.0]);
            let out: f64 = (0..3).map(|k| n[k] * (centre[k] - 0.5)).sum();
            assert!(out > 0.0 && ((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn the_faces_at_the_closest_point_are_those_a_brute_force_finds() {
        let s = cube();
        // Inside a face, on an edge (two triangles of one face and two of the next), at a
        // corner, and on a face's diagonal.
        for (q, expected) in [
            ([0.3, 0.6, 4.0], vec![3_usize]),
            ([0.5, -3.0, -3.0], vec![1, 4]),
            ([2.0, 2.0, 2.0], vec![2, 3, 6, 7, 10, 11]),
            ([0.5, 0.5, 5.0], vec![2, 3]),
        ] {
            let (point, faces) = s.faces_at_closest(q).unwrap();
            // Brute force: every triangle, by its distance to the closest point.
            let brute: Vec<usize> = (0..12)
                .filter(|&f| {
                    let [a, b, c] = s.triangle(f);
                    let t = parry3d_f64::shape::Triangle::new(a, b, c);
                    parry3d_f64::query::PointQuery::distance_to_local_point(&t, crate::geometry::v(point), false) < 1e-12
                })
                .collect();
            assert_eq!(faces, brute, "query {q:?}");
            assert_eq!(faces, expected, "query {q:?}");
        }
    }
}
