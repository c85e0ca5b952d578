//! Degrees of freedom and the boundary conditions of spec §5 expressed on them.
//!
//! Every control point ("node") of every body carries `n_fields` field
//! components (displacements, then temperature, as the physics needs). A
//! component is either *fixed* (Dirichlet: prescribed value) or belongs to an
//! equation. Several components may share one equation (*ties*): periodic
//! lateral conditions `u+ = u−`, `θ+ = θ−` (2.3), and the rigid platen whose
//! top control points share one vertical displacement unknown (spec §5), the
//! conjugate equation of which is the total vertical force.

use crate::{Error, Result};

/// The role of one field component of one node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Dof {
    /// An unknown: the equation number.
    Free(usize),
    /// Prescribed (Dirichlet) value, reached at load factor 1.
    Fixed(f64),
}

/// Collects Dirichlet conditions and ties, then numbers the equations.
#[derive(Clone, Debug)]
pub struct DofMapBuilder {
    n_nodes: usize,
    n_fields: usize,
    fixed: Vec<Option<f64>>,
    parent: Vec<usize>,
}

impl DofMapBuilder {
    /// `n_nodes` nodes with `n_fields` components each, all free and untied.
    pub fn new(n_nodes: usize, n_fields: usize) -> Self {
        let n = n_nodes * n_fields;
        DofMapBuilder {
            n_nodes,
            n_fields,
            fixed: vec![None; n],
            parent: (0..n).collect(),
        }
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.n_nodes
    }

    /// Number of field components per node.
    pub fn n_fields(&self) -> usize {
        self.n_fields
    }

    #[track_caller]
    fn slot(&self, node: usize, field: usize) -> usize {
        assert!(
            node < self.n_nodes && field < self.n_fields,
            "dof ({node}, {field}) out of range"
        );
        node * self.n_fields + field
    }

    fn root(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    /// Prescribes `value` for component `field` of `node`.
    #[track_caller]
    pub fn fix(&mut self, node: usize, field: usize, value: f64) {
        let s = self.slot(node, field);
        self.fixed[s] = Some(value);
    }

    /// Makes two components share one unknown (their residuals add).
    #[track_caller]
    pub fn tie(&mut self, a: (usize, usize), b: (usize, usize)) {
        let (sa, sb) = (self.slot(a.0, a.1), self.slot(b.0, b.1));
        let (ra, rb) = (self.root(sa), self.root(sb));
        if ra != rb {
            // Keep the smaller slot as the root: numbering follows node order.
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            self.parent[hi] = lo;
        }
    }

    /// Numbers the equations in node order. A tie group containing a fixed
    /// component is fixed as a whole; conflicting prescribed values in one
    /// group are an error.
    pub fn build(mut self) -> Result<DofMap> {
        let n = self.fixed.len();
        let mut group_fixed: Vec<Option<f64>> = vec![None; n];
        for s in 0..n {
            if let Some(v) = self.fixed[s] {
                let r = self.root(s);
                match group_fixed[r] {
                    Some(w) if (w - v).abs() > 1e-14 * w.abs().max(v.abs()).max(1.0) => {
                        return Err(Error::invalid(
                            "boundary conditions",
                            format!("{w} and {v}"),
                            "tied degrees of freedom must not be prescribed different values",
                        ));
                    }
                    _ => group_fixed[r] = Some(v),
                }
            }
        }
        let mut eq_of_root = vec![usize::MAX; n];
        let mut dofs = Vec::with_capacity(n);
        let mut eq_field = Vec::new();
        for s in 0..n {
            let r = self.root(s);
            if let Some(v) = group_fixed[r] {
                dofs.push(Dof::Fixed(self.fixed[s].unwrap_or(v)));
            } else {
                if eq_of_root[r] == usize::MAX {
                    eq_of_root[r] = eq_field.len();
                    eq_field.push(s % self.n_fields);
                }
                dofs.push(Dof::Free(eq_of_root[r]));
            }
        }
        Ok(DofMap {
            n_nodes: self.n_nodes,
            n_fields: self.n_fields,
            dofs,
            eq_field,
        })
    }
}

/// The numbered degrees of freedom.
#[derive(Clone, Debug)]
pub struct DofMap {
    n_nodes: usize,
    n_fields: usize,
    dofs: Vec<Dof>,
    eq_field: Vec<usize>,
}

impl DofMap {
    /// Whether `other` numbers the same equations: the same components free, each with the
    /// same equation, whatever the prescribed values.
    pub fn same_equations(&self, other: &DofMap) -> bool {
        self.n_fields == other.n_fields
            && self.eq_field == other.eq_field
            && self.dofs.len() == other.dofs.len()
            && self
                .dofs
                .iter()
                .zip(&other.dofs)
                .all(|(a, b)| match (a, b) {
                    (Dof::Free(i), Dof::Free(j)) => i == j,
                    (Dof::Fixed(_), Dof::Fixed(_)) => true,
                    _ => false,
                })
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.n_nodes
    }

    /// Field components per node.
    pub fn n_fields(&self) -> usize {
        self.n_fields
    }

    /// Number of equations (unknowns).
    pub fn n_eq(&self) -> usize {
        self.eq_field.len()
    }

    /// Length of a state vector (all components of all nodes).
    pub fn n_state(&self) -> usize {
        self.dofs.len()
    }

    /// The field component that each equation belongs to.
    pub fn eq_fields(&self) -> &[usize] {
        &self.eq_field
    }

    /// The role of component `field` of `node`.
    #[track_caller]
    pub fn dof(&self, node: usize, field: usize) -> Dof {
        self.dofs[node * self.n_fields + field]
    }

    /// The equation of a component, `None` if it is prescribed.
    #[track_caller]
    pub fn eq(&self, node: usize, field: usize) -> Option<usize> {
        match self.dof(node, field) {
            Dof::Free(e) => Some(e),
            Dof::Fixed(_) => None,
        }
    }

    /// Changes the prescribed value of a fixed component (no effect on free ones).
    #[track_caller]
    pub fn set_fixed(&mut self, node: usize, field: usize, value: f64) {
        let s = node * self.n_fields + field;
        if let Dof::Fixed(_) = self.dofs[s] {
            self.dofs[s] = Dof::Fixed(value);
        }
    }

    /// Whether every prescribed component of `initial` holds its value already
    /// ([`DofMap::impose`] then leaves them where they are at every factor).
    pub fn prescribed_in(&self, initial: &[f64]) -> bool {
        self.dofs
            .iter()
            .zip(initial)
            .all(|(d, &x)| !matches!(*d, Dof::Fixed(v) if v != x))
    }

    /// Sets every prescribed component of `state` to its value exactly.
    pub fn hold(&self, state: &mut [f64]) {
        for (s, d) in self.dofs.iter().enumerate() {
            if let Dof::Fixed(v) = *d {
                state[s] = v;
            }
        }
    }

    /// Sets the prescribed components of `state` to `initial + factor (value − initial)`.
    pub fn impose(&self, state: &mut [f64], initial: &[f64], factor: f64) {
        for (s, d) in self.dofs.iter().enumerate() {
            if let Dof::Fixed(v) = *d {
                state[s] = initial[s] + factor * (v - initial[s]);
            }
        }
    }

    /// Adds an increment of the unknowns to every component that carries them.
    pub fn add_increment(&self, dx: &[f64], state: &mut [f64]) {
        for (s, d) in self.dofs.iter().enumerate() {
            if let Dof::Free(e) = *d {
                state[s] += dx[e];
            }
        }
    }

    /// Sums a state-space vector (e.g. nodal forces) into equation space:
    /// tied components add, prescribed ones are dropped.
    pub fn gather(&self, state_vec: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|v| *v = 0.0);
        for (s, d) in self.dofs.iter().enumerate() {
            if let Dof::Free(e) = *d {
                out[e] += state_vec[s];
            }
        }
    }

    /// Equations of the components `fields` of the nodes `conn` (node-major).
    pub fn element_eqs(&self, conn: &[usize], fields: &[usize]) -> Vec<Option<usize>> {
        let mut v = Vec::with_capacity(conn.len() * fields.len());
        for &n in conn {
            for &f in fields {
                v.push(self.eq(n, f));
            }
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ties_share_an_equation_and_fixed_groups_are_fixed() {
        let mut b = DofMapBuilder::new(4, 2);
        b.tie((0, 1), (3, 1));
        b.tie((1, 0), (2, 0));
        b.fix(2, 0, 5.0);
        let m = b.build().unwrap();
        assert_eq!(m.eq(0, 1), m.eq(3, 1));
        assert!(m.eq(0, 1).is_some());
        assert_eq!(m.dof(1, 0), Dof::Fixed(5.0));
        assert_eq!(m.n_eq(), 8 - 2 - 1);
        let mut out = vec![0.0; m.n_eq()];
        m.gather(&[1.0; 8], &mut out);
        assert_eq!(out[m.eq(0, 1).unwrap()], 2.0);
    }

    #[test]
    fn conflicting_prescriptions_are_rejected() {
        let mut b = DofMapBuilder::new(2, 1);
        b.tie((0, 0), (1, 0));
        b.fix(0, 0, 1.0);
        b.fix(1, 0, 2.0);
        assert!(b.build().is_err());
    }
}
