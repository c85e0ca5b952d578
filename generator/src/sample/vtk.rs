//! ParaView output of a solved micro-sample (legacy VTK, ASCII): each body
//! sampled on a structured grid in its deformed configuration with the
//! displacement, temperature, Cauchy stress and spatial heat flux, and the
//! contact interface (slave control points) with the lumped contact pressure
//! and interface heat flux. All values in SI.

use std::fmt::Write as _;
use std::path::Path;

use nalgebra::{Matrix3, Vector3};

use crate::solve::Model;
use crate::{Error, Result};

/// Samples per element and direction.
const SAMPLES: usize = 4;

fn write_file(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).map_err(|e| Error::Io {
        path: path.display().to_string(),
        source: e,
    })
}

/// Writes `{prefix}_{body}.vtk` for every body and `{prefix}_interface.vtk` into `dir`.
pub fn write_model(model: &Model, dir: &Path, prefix: &str) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::Io {
        path: dir.display().to_string(),
        source: e,
    })?;
    let s = model.scales;
    let nf = model.dim + 1;
    for body in &model.bodies {
        let kv = body.patch.knots();
        let axes: Vec<Vec<f64>> = kv
            .iter()
            .map(|k| {
                let spans = k.element_spans();
                let mut v = Vec::new();
                for (n, &sp) in spans.iter().enumerate() {
                    let (a, b) = (k.knots()[sp], k.knots()[sp + 1]);
                    let first = if n == 0 { 0 } else { 1 };
                    for t in first..=SAMPLES {
                        v.push(a + (b - a) * t as f64 / SAMPLES as f64);
                    }
                }
                v
            })
            .collect();
        let (nx, ny) = (axes[0].len(), axes[1].len());
        let mut pts = String::new();
        let (mut disp, mut temp, mut stress, mut flux) =
            (String::new(), String::new(), String::new(), String::new());
        for &eta in &axes[1] {
            for &xi in &axes[0] {
                let b = body.patch.basis(&[xi, eta], 1);
                // Reference Jacobian and position.
                let (mut x, mut jac) = ([0.0; 2], [[0.0; 2]; 2]);
                let (mut u, mut th) = ([0.0; 2], 0.0);
                let (mut gu, mut gt) = ([[0.0; 2]; 2], [0.0; 2]);
                for (a, &c) in b.indices.iter().enumerate() {
                    let xa = body.patch.control_points()[c];
                    let st = &model.state[(c + body.node_offset) * nf..];
                    for i in 0..2 {
                        x[i] += b.values[a] * xa[i];
                        u[i] += b.values[a] * st[i];
                        for k in 0..2 {
                            jac[i][k] += xa[i] * b.d1[a][k];
                        }
                    }
                    th += b.values[a] * st[2];
                }
                let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
                let inv = [
                    [jac[1][1] / det, -jac[0][1] / det],
                    [-jac[1][0] / det, jac[0][0] / det],
                ];
                for (a, &c) in b.indices.iter().enumerate() {
                    let st = &model.state[(c + body.node_offset) * nf..];
                    // dR/dX_j = Σ_k dR/dξ_k (J⁻¹)_kj
                    let dx = [
                        b.d1[a][0] * inv[0][0] + b.d1[a][1] * inv[1][0],
                        b.d1[a][0] * inv[0][1] + b.d1[a][1] * inv[1][1],
                    ];
                    for i in 0..2 {
                        for j in 0..2 {
                            gu[i][j] += st[i] * dx[j];
                        }
                        gt[i] += st[2] * dx[i];
                    }
                }
                let mut f = Matrix3::identity();
                for i in 0..2 {
                    for j in 0..2 {
                        f[(i, j)] += gu[i][j];
                    }
                }
                let m = &body.material;
                let sigma = m.cauchy_stress(&f, th) * s.stress;
                let q0 = m.heat_flux(&f, th, &Vector3::new(gt[0], gt[1], 0.0));
                let q = f * q0 / f.determinant() * s.flux();
                let _ = writeln!(
                    pts,
                    "{:e} {:e} 0",
                    (x[0] + u[0]) * s.length,
                    (x[1] + u[1]) * s.length
                );
                let _ = writeln!(disp, "{:e} {:e} 0", u[0] * s.length, u[1] * s.length);
                let _ = writeln!(temp, "{:e}", th * s.temperature);
                let _ = writeln!(
                    stress,
                    "{:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e}",
                    sigma[(0, 0)],
                    sigma[(0, 1)],
                    sigma[(0, 2)],
                    sigma[(1, 0)],
                    sigma[(1, 1)],
                    sigma[(1, 2)],
                    sigma[(2, 0)],
                    sigma[(2, 1)],
                    sigma[(2, 2)]
                );
                let _ = writeln!(flux, "{:e} {:e} 0", q[0], q[1]);
            }
        }
        let n = nx * ny;
        let mut t = format!(
            "# vtk DataFile Version 3.0\ntcgen micro-sample body {} (deformed, SI)\nASCII\nDATASET STRUCTURED_GRID\nDIMENSIONS {nx} {ny} 1\nPOINTS {n} double\n{pts}",
            body.name
        );
        let _ = write!(
            t,
            "POINT_DATA {n}\nVECTORS displacement double\n{disp}SCALARS temperature double 1\nLOOKUP_TABLE default\n{temp}TENSORS cauchy_stress double\n{stress}VECTORS heat_flux double\n{flux}"
        );
        write_file(&dir.join(format!("{prefix}_{}.vtk", body.name)), &t)?;
    }
    if let Some(c) = &model.contact {
        let ns = c.n_slave();
        let mut pts = String::new();
        let (mut p, mut h, mut g) = (String::new(), String::new(), String::new());
        for i in 0..ns {
            let node = c.slave_nodes[i];
            let x = model.node_reference(node);
            let ux = model.displacement(node, 0);
            let uy = model.displacement(node, 1);
            let _ = writeln!(
                pts,
                "{:e} {:e} 0",
                x[0] * s.length + ux,
                x[1] * s.length + uy
            );
            let _ = writeln!(p, "{:e}", c.pressure(i).max(0.0) * s.stress);
            let _ = writeln!(h, "{:e}", c.heat_flux(i) * s.flux());
            let _ = writeln!(g, "{:e}", c.weighted_gap(i) * s.length);
        }
        let mut t = format!(
            "# vtk DataFile Version 3.0\ntcgen contact interface (slave control points, SI)\nASCII\nDATASET POLYDATA\nPOINTS {ns} double\n{pts}LINES 1 {}\n{ns}",
            ns + 1
        );
        for i in 0..ns {
            let _ = write!(t, " {i}");
        }
        let _ = write!(
            t,
            "\nPOINT_DATA {ns}\nSCALARS contact_pressure double 1\nLOOKUP_TABLE default\n{p}SCALARS interface_heat_flux double 1\nLOOKUP_TABLE default\n{h}SCALARS weighted_gap double 1\nLOOKUP_TABLE default\n{g}"
        );
        write_file(&dir.join(format!("{prefix}_interface.vtk")), &t)?;
    }
    Ok(())
}
