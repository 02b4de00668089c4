//! Triangle meshes of objects in their own flat object space: the built-in shapes
//! ([`procedural`]) and meshes read from OBJ, PLY and glTF/GLB files ([`import`]).
//!
//! Object space is Euclidean with **Y up** (the glTF convention, and what most OBJ and PLY
//! files use); embedding into the room (ARCHITECTURE.md §7) maps x and z through the exponential map
//! and y to height.

pub mod import;
pub mod procedural;

/// An indexed triangle mesh in object space (Y up), counter-clockwise seen from outside.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub positions: Vec<[f64; 3]>,
    /// Triangles as indices into `positions`.
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// The smallest axis-aligned box holding every vertex, as (min, max); `None` when empty.
    pub fn bounds(&self) -> Option<([f64; 3], [f64; 3])> {
        let first = *self.positions.first()?;
        Some(self.positions.iter().fold((first, first), |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])],
                [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])],
            )
        }))
    }
}

impl TriangleMesh {
    /// Appends the vertices and triangles of `other`, re-indexing its triangles.
    ///
    /// # Panics
    ///
    /// When the result would have more than `u32::MAX` vertices.
    pub fn append(&mut self, other: &TriangleMesh) {
        let base = self.positions.len();
        assert!(
            u32::try_from(base + other.positions.len()).is_ok(),
            "a triangle mesh has at most u32::MAX vertices"
        );
        let base = base as u32;
        self.positions.extend_from_slice(&other.positions);
        self.triangles
            .extend(other.triangles.iter().map(|t| t.map(|i| i + base)));
    }

    /// Applies the affine map p ↦ A·p + t (`linear` holds the rows of A). When det A < 0 the
    /// triangles are reversed, so that an outward-oriented mesh stays outward-oriented.
    pub fn transform(&mut self, linear: [[f64; 3]; 3], offset: [f64; 3]) {
        for p in &mut self.positions {
            let q = *p;
            *p = [0, 1, 2].map(|r| {
                linear[r][0] * q[0] + linear[r][1] * q[1] + linear[r][2] * q[2] + offset[r]
            });
        }
        let [a, b, c] = linear;
        let det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0]);
        if det < 0.0 {
            self.flip();
        }
    }

    /// Moves every vertex by `offset`.
    pub fn translate(&mut self, offset: [f64; 3]) {
        for p in &mut self.positions {
            *p = [p[0] + offset[0], p[1] + offset[1], p[2] + offset[2]];
        }
    }

    /// Reverses the orientation of every triangle (turns the mesh inside out).
    pub fn flip(&mut self) {
        for t in &mut self.triangles {
            t.swap(1, 2);
        }
    }

    /// The signed volume enclosed by the mesh: positive for a closed mesh oriented outward
    /// (counter-clockwise seen from outside), the sum over parts for a mesh of several closed
    /// parts. Triangles with an index out of range are skipped.
    pub fn signed_volume(&self) -> f64 {
        self.tetrahedra().map(|(v, _)| v).sum()
    }

    /// The centre of mass of the solid the mesh encloses, at uniform density (for a mesh of
    /// several closed parts, each part counts with its own volume); `None` when the enclosed
    /// volume is not positive.
    pub fn centre_of_mass(&self) -> Option<[f64; 3]> {
        let volume = self.signed_volume();
        (volume > 0.0 && volume.is_finite())
            .then(|| orbifold::embed::centre_of_mass(&self.positions, &self.triangles).to_array())
    }

    /// The signed volume and centroid of the tetrahedron from a reference point to each
    /// triangle. The reference point is the first vertex, which keeps the sums accurate for
    /// meshes far from the origin.
    fn tetrahedra(&self) -> impl Iterator<Item = (f64, [f64; 3])> + '_ {
        let o = self.positions.first().copied().unwrap_or_default();
        self.triangles.iter().filter_map(move |t| {
            let [a, b, c] = [
                self.positions.get(t[0] as usize)?,
                self.positions.get(t[1] as usize)?,
                self.positions.get(t[2] as usize)?,
            ]
            .map(|p| [p[0] - o[0], p[1] - o[1], p[2] - o[2]]);
            let volume = (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0;
            let centroid = [0, 1, 2].map(|k| o[k] + (a[k] + b[k] + c[k]) / 4.0);
            Some((volume, centroid))
        })
    }
}
