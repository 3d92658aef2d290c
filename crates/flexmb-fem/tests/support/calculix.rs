//! CalculiX (`ccx`) as an outside check of flexmb's finite-element results: decks of a cantilever
//! beam of B31 elements and of a cantilever S4 plate, each with a `*FREQUENCY` step, and the natural
//! frequencies ccx finds for a deck.
//!
//! ccx is the Debian package `calculix-ccx`; tests skip when it is not on the PATH. Note that ccx
//! expands B31 beams and S4 shells into 3D solid elements and uses a consistent mass, so expect
//! differences of the order of 1 % against beam or plate theory and against flexmb's lumped masses.
#![allow(dead_code)]

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The `ccx` executable on the PATH, if any.
pub fn ccx_path() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join("ccx"))
        .find(|candidate| is_executable(candidate))
}

fn is_executable(path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        path.metadata()
            .is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
    }
    #[cfg(not(unix))]
    {
        path.is_file()
    }
}

/// Writes `inp_text` to `work_dir/job.inp`, runs `ccx -i job` there (one thread) and returns the
/// frequencies (cycles/time) of the first eigenvalue table of `job.dat`, in ccx's order (ascending).
pub fn natural_frequencies(inp_text: &str, work_dir: &Path) -> Result<Vec<f64>, String> {
    let (text, dat) = run(inp_text, work_dir)?;
    parse_eigenvalue_table(&text).ok_or_else(|| format!("no eigenvalue table in {}", dat.display()))
}

/// Runs ccx on a deck with a `*STATIC` step and a `*NODE PRINT` of `U` and returns the printed
/// nodal displacements (label, ux, uy, uz) of the first table of `job.dat`.
pub fn static_displacements(inp_text: &str, work_dir: &Path) -> Result<Vec<(u64, [f64; 3])>, String> {
    let (text, dat) = run(inp_text, work_dir)?;
    let mut lines = text.lines().skip_while(|l| !l.contains("displacements (vx,vy,vz)"));
    lines.next().ok_or_else(|| format!("no displacement table in {}", dat.display()))?;
    let mut rows = Vec::new();
    for line in lines {
        let fields: Vec<&str> = line.split_whitespace().collect();
        if fields.is_empty() && rows.is_empty() {
            continue;
        }
        let (Some(label), Some(values)) = (
            fields.first().and_then(|f| f.parse::<u64>().ok()),
            fields.get(1..4).and_then(|v| v.iter().map(|x| x.parse::<f64>().ok()).collect::<Option<Vec<f64>>>()),
        ) else {
            break;
        };
        rows.push((label, [values[0], values[1], values[2]]));
    }
    Ok(rows)
}

/// Runs ccx on `inp_text` in `work_dir` (as `job.inp`), for the files it writes there.
pub fn run_deck(inp_text: &str, work_dir: &Path) -> Result<(), String> {
    run(inp_text, work_dir).map(|_| ())
}

/// Runs ccx on `inp_text` in `work_dir` and returns the text and the path of `job.dat`.
fn run(inp_text: &str, work_dir: &Path) -> Result<(String, PathBuf), String> {
    let ccx =
        ccx_path().ok_or("ccx not found on the PATH (install Debian package calculix-ccx)")?;
    std::fs::create_dir_all(work_dir)
        .map_err(|e| format!("cannot create {}: {e}", work_dir.display()))?;
    let dat = work_dir.join("job.dat");
    let _ = std::fs::remove_file(&dat);
    std::fs::write(work_dir.join("job.inp"), inp_text)
        .map_err(|e| format!("cannot write {}: {e}", work_dir.join("job.inp").display()))?;
    let output = Command::new(&ccx)
        .args(["-i", "job"])
        .current_dir(work_dir)
        .env("OMP_NUM_THREADS", "1")
        .env("CCX_NPROC_EQUATION_SOLVER", "1")
        .output()
        .map_err(|e| format!("cannot run {}: {e}", ccx.display()))?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    let errors: Vec<&str> = stdout.lines().filter(|l| l.contains("*ERROR")).collect();
    if !output.status.success() || !errors.is_empty() {
        let tail: Vec<&str> = stdout
            .lines()
            .rev()
            .take(20)
            .collect::<Vec<_>>()
            .into_iter()
            .rev()
            .collect();
        return Err(format!(
            "ccx failed ({}) in {}:\n{}\n{}",
            output.status,
            work_dir.display(),
            errors.join("\n"),
            tail.join("\n")
        ));
    }
    let text =
        std::fs::read_to_string(&dat).map_err(|e| format!("cannot read {}: {e}", dat.display()))?;
    Ok((text, dat))
}

/// The frequencies (cycles/time, the fourth column) of the first `E I G E N V A L U E   O U T P U T`
/// table of a ccx `.dat` file.
pub fn parse_eigenvalue_table(dat: &str) -> Option<Vec<f64>> {
    let mut lines = dat
        .lines()
        .skip_while(|l| !l.contains("E I G E N V A L U E   O U T P U T"));
    lines.next()?;
    let mut frequencies = Vec::new();
    for line in lines {
        let fields: Vec<&str> = line.split_whitespace().collect();
        let mode = fields.first().and_then(|f| f.parse::<usize>().ok());
        match (mode, fields.get(3).and_then(|f| f.parse::<f64>().ok())) {
            (Some(_), Some(f)) if fields.len() >= 4 => frequencies.push(f),
            // Blank lines and the column headers come before the rows; anything else ends them.
            _ if frequencies.is_empty() => continue,
            _ => break,
        }
    }
    (!frequencies.is_empty()).then_some(frequencies)
}

/// A cantilever of B31 elements along x from the origin, clamped at x = 0, with a solid rectangular
/// section: `a` along the first section direction n₁ = y, `b` along n₂ = z.
#[derive(Clone, Debug)]
pub struct CantileverBeam {
    pub length: f64,
    pub elements: usize,
    pub a: f64,
    pub b: f64,
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    pub density: f64,
    pub modes: usize,
}

impl Default for CantileverBeam {
    /// 1 m of steel, 20 elements, 20 mm × 10 mm, 8 modes.
    fn default() -> Self {
        CantileverBeam {
            length: 1.0,
            elements: 20,
            a: 0.02,
            b: 0.01,
            youngs_modulus: 210e9,
            poisson_ratio: 0.3,
            density: 7850.0,
            modes: 8,
        }
    }
}

impl CantileverBeam {
    /// The deck: nodes 1…n+1 along x, elements 1…n, node set `ROOT` clamped, node set `TIP`, a
    /// `*FREQUENCY` step.
    pub fn deck(&self) -> String {
        let mut s = String::new();
        let n = self.elements;
        s += "** flexmb test deck: cantilever of B31 beams, clamped at x = 0\n*NODE, NSET=NALL\n";
        for i in 0..=n {
            let _ = writeln!(
                s,
                "{}, {}, 0., 0.",
                i + 1,
                self.length * i as f64 / n as f64
            );
        }
        s += "*ELEMENT, TYPE=B31, ELSET=EBEAM\n";
        for i in 1..=n {
            let _ = writeln!(s, "{i}, {i}, {}", i + 1);
        }
        let _ = writeln!(s, "*NSET, NSET=ROOT\n1\n*NSET, NSET=TIP\n{}", n + 1);
        let _ = writeln!(
            s,
            "*MATERIAL, NAME=MAT\n*ELASTIC\n{}, {}\n*DENSITY\n{}",
            self.youngs_modulus, self.poisson_ratio, self.density
        );
        let _ = writeln!(
            s,
            "*BEAM SECTION, ELSET=EBEAM, MATERIAL=MAT, SECTION=RECT\n{}, {}\n0., 1., 0.",
            self.a, self.b
        );
        s += "*BOUNDARY\nROOT, 1, 6\n";
        let _ = writeln!(s, "*STEP\n*FREQUENCY\n{}\n*END STEP", self.modes);
        s
    }

    /// The first bending frequency (Hz) of Euler–Bernoulli theory, about the weaker axis:
    /// `(1.8751)² / (2π) √(E I / (ρ A L⁴))`.
    pub fn first_bending_frequency(&self) -> f64 {
        let i = (self.a * self.b.powi(3)).min(self.b * self.a.powi(3)) / 12.0;
        let area = self.a * self.b;
        1.875_104_068_711_961_f64.powi(2) / (2.0 * std::f64::consts::PI)
            * (self.youngs_modulus * i / (self.density * area * self.length.powi(4))).sqrt()
    }
}

/// A flat rectangular plate of S4 shells in the x–y plane, `lx` × `ly`, `nx` × `ny` elements, clamped
/// along x = 0: node `i + (nx + 1) j + 1` is at `(i lx / nx, j ly / ny, 0)`.
#[derive(Clone, Debug)]
pub struct CantileverPlate {
    pub lx: f64,
    pub ly: f64,
    pub nx: usize,
    pub ny: usize,
    pub thickness: f64,
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    pub density: f64,
    pub modes: usize,
}

impl Default for CantileverPlate {
    /// 0.4 m × 0.2 m × 2 mm of aluminium, 16 × 8 elements, 8 modes.
    fn default() -> Self {
        CantileverPlate {
            lx: 0.4,
            ly: 0.2,
            nx: 16,
            ny: 8,
            thickness: 0.002,
            youngs_modulus: 70e9,
            poisson_ratio: 0.33,
            density: 2700.0,
            modes: 8,
        }
    }
}

impl CantileverPlate {
    /// The deck: node set `CLAMPED` (x = 0), element set `PLATE`, a `*FREQUENCY` step.
    pub fn deck(&self) -> String {
        let (nx, ny) = (self.nx, self.ny);
        let node = |i: usize, j: usize| i + (nx + 1) * j + 1;
        let mut s = String::new();
        s += "** flexmb test deck: cantilever plate of S4 shells, clamped along x = 0\n*NODE\n";
        for j in 0..=ny {
            for i in 0..=nx {
                let (x, y) = (
                    self.lx * i as f64 / nx as f64,
                    self.ly * j as f64 / ny as f64,
                );
                let _ = writeln!(s, "{}, {x}, {y}, 0.", node(i, j));
            }
        }
        s += "*ELEMENT, TYPE=S4, ELSET=PLATE\n";
        let mut label = 0;
        for j in 0..ny {
            for i in 0..nx {
                label += 1;
                let _ = writeln!(
                    s,
                    "{label}, {}, {}, {}, {}",
                    node(i, j),
                    node(i + 1, j),
                    node(i + 1, j + 1),
                    node(i, j + 1)
                );
            }
        }
        let _ = writeln!(
            s,
            "*NSET, NSET=CLAMPED, GENERATE\n1, {}, {}",
            node(0, ny),
            nx + 1
        );
        let _ = writeln!(
            s,
            "*MATERIAL, NAME=MAT\n*ELASTIC\n{}, {}\n*DENSITY\n{}",
            self.youngs_modulus, self.poisson_ratio, self.density
        );
        let _ = writeln!(
            s,
            "*SHELL SECTION, ELSET=PLATE, MATERIAL=MAT\n{}",
            self.thickness
        );
        s += "*BOUNDARY\nCLAMPED, 1, 6\n";
        let _ = writeln!(s, "*STEP\n*FREQUENCY\n{}\n*END STEP", self.modes);
        s
    }

    /// The first bending frequency (Hz) of the plate taken as a cantilever beam of width `ly` with
    /// the plate's bending stiffness D = E t³ / 12 (1 − ν²) per unit width — close to the plate's
    /// first mode for a plate longer than wide (the clamp's anticlastic restraint stiffens it a
    /// little).
    pub fn first_bending_frequency_beam_estimate(&self) -> f64 {
        let d = self.youngs_modulus * self.thickness.powi(3)
            / (12.0 * (1.0 - self.poisson_ratio.powi(2)));
        1.875_104_068_711_961_f64.powi(2) / (2.0 * std::f64::consts::PI)
            * (d / (self.density * self.thickness * self.lx.powi(4))).sqrt()
    }
}
