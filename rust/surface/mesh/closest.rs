//! Which triangle holds the closest point, and each triangle's unit normal: the mesh geometry
//! the Python layers ask for (closest face of a target, the outward normal a start flies out
//! along, the share of a reconstruction facing the wrong way), answered here once.

use parry3d_f64::query::PointQueryWithLocation;

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
}
