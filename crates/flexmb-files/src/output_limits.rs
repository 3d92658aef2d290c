//! How much a simulation may write before it starts: output rows (the CSV and the rows kept in memory
//! by `compare`) and ParaView frames (one file per body and joint each). A mistyped output step
//! (`1e-9` for `1e-3`) would otherwise fill the disk for hours; it is refused with the count it would
//! make and how to allow it.

/// Most output rows a run writes unless allowed more (`--max-output-rows`, `[simulation]
/// max_output_rows`): 10⁷, about 2 GB of CSV for 20 columns.
pub const DEFAULT_MAX_OUTPUT_ROWS: u64 = 10_000_000;

/// Most ParaView frames a run writes unless allowed more (`--max-vtk-frames`, `[simulation]
/// max_vtk_frames`): 10⁵, each a file per body and joint.
pub const DEFAULT_MAX_VTK_FRAMES: u64 = 100_000;

/// The number of output times `0, h, 2h, …` up to `t_end` (the engine's grid: `⌊t_end/h⌋ + 1`), as a
/// float, since it may exceed every integer type.
pub fn grid_count(t_end: f64, step: f64) -> f64 {
    (t_end / step * (1.0 + 1e-12)).floor() + 1.0
}

/// An error if outputs every `output_step` up to `t_end` make more than `limit` rows. With
/// `command_line`, the message offers `--max-output-rows` as well as the `[simulation]` key.
pub fn check_output_rows(t_end: f64, output_step: f64, limit: u64, command_line: bool) -> Result<(), String> {
    let rows = grid_count(t_end, output_step);
    if rows <= limit as f64 {
        return Ok(());
    }
    Err(format!(
        "an output step of {} s up to t_end = {} s would write {} output rows, more than the limit of {limit}: \
         give a longer output step, or allow them with {}",
        number_text(output_step),
        number_text(t_end),
        count_text(rows),
        allowance("max-output-rows", rows, command_line)
    ))
}

/// An error if ParaView frames every `frame_step` up to `t_end` are more than `limit`.
pub fn check_vtk_frames(t_end: f64, frame_step: f64, limit: u64) -> Result<(), String> {
    let frames = grid_count(t_end, frame_step);
    if frames <= limit as f64 {
        return Ok(());
    }
    Err(format!(
        "ParaView frames every {} s up to t_end = {} s would be {} frames (a file per body and joint each), \
         more than the limit of {limit}: give a longer --vtk-step, or allow them with {}",
        number_text(frame_step),
        number_text(t_end),
        count_text(frames),
        allowance("max-vtk-frames", frames, true)
    ))
}

/// How to allow `count`: the option `--NAME`, and the `[simulation]` key of the same name.
fn allowance(name: &str, count: f64, command_line: bool) -> String {
    let count = count_text(count);
    let key = name.replace('-', "_");
    if command_line {
        format!("--{name} {count} (or {key} = {count} in the model's [simulation])")
    } else {
        format!("{key} = {count} in the model's [simulation]")
    }
}

/// A count as a whole number, or in scientific notation beyond 10¹⁵.
fn count_text(count: f64) -> String {
    if count < 1e15 {
        format!("{count:.0}")
    } else {
        format!("{count:.3e}")
    }
}

/// A time as written if it is of ordinary size, else in scientific notation.
fn number_text(x: f64) -> String {
    if x == 0.0 || (1e-4..1e7).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_the_engines_output_grid() {
        assert_eq!(grid_count(5.0, 0.01), 501.0);
        assert_eq!(grid_count(0.3, 0.1), 4.0, "0.3/0.1 is 2.9999999999999996 in floating point");
        assert_eq!(grid_count(1.0, 0.3), 4.0);
        assert!((grid_count(1.0, 1e-300) / 1e300 - 1.0).abs() < 1e-11);
    }

    #[test]
    fn too_many_rows_are_refused_with_the_count_and_how_to_allow_them() {
        assert!(check_output_rows(5.0, 0.01, 501, true).is_ok());
        let e = check_output_rows(5.0, 0.01, 500, true).unwrap_err();
        assert_eq!(
            e,
            "an output step of 0.01 s up to t_end = 5 s would write 501 output rows, more than the limit of 500: \
             give a longer output step, or allow them with --max-output-rows 501 (or max_output_rows = 501 in \
             the model's [simulation])"
        );
        let e = check_output_rows(1.0, 1e-300, DEFAULT_MAX_OUTPUT_ROWS, false).unwrap_err();
        assert!(e.starts_with("an output step of 1e-300 s up to t_end = 1 s would write 1.000e300 output rows"), "{e}");
        assert!(e.ends_with("with max_output_rows = 1.000e300 in the model's [simulation]"), "{e}");
        let e = check_vtk_frames(1000.0, 1e-3, DEFAULT_MAX_VTK_FRAMES).unwrap_err();
        assert!(e.contains("would be 1000001 frames") && e.contains("--max-vtk-frames 1000001 (or max_vtk_frames"), "{e}");
    }
}
