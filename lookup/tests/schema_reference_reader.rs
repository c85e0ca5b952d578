//! The Python reference reader printed in `schemas/law.md` reads a file written
//! by `Law::write` and finds the same axes, metadata and arrays: the
//! specification and the implementation agree. Needs `python3`; where it is
//! not installed the test says so and checks nothing else.

mod common;

use common::*;
use lookup::Extrapolation;
use std::path::PathBuf;
use std::process::Command;

#[test]
fn schema_reference_reader_agrees_with_the_writer() {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let schema =
        std::fs::read_to_string(manifest.join("../schemas/law.md")).expect("schemas/law.md");
    let start = schema
        .find("```python\n")
        .expect("python block in the schema")
        + "```python\n".len();
    let code = &schema[start..start + schema[start..].find("```").unwrap()];

    let tmp = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("schema");
    std::fs::create_dir_all(&tmp).unwrap();
    let base = law_from(table_axes(6, 3, 2), physical_jump, Extrapolation::Linear);
    let error: Vec<f64> = base.jump_mean().iter().map(|m| 0.003 * m).collect();
    let law = lookup::Law::from_grid_with_error(
        base.axes().clone(),
        base.jump_mean().to_vec(),
        base.jump_std().to_vec(),
        Some(error),
        base.info().clone(),
    )
    .unwrap();
    let path = tmp.join("law.tclaw");
    law.write(&path).unwrap();
    let script = format!(
        "{code}\nimport sys\nmeta, p, h, t, mean, std, error = read_law(sys.argv[1])\n\
         print('statistic', meta['statistic'])\nprint('flux_policy', meta['extrapolation.flux'])\n\
         print('error_key', meta['discretization_error'])\n\
         for name, a in (('p', p), ('h', h), ('t', t), ('mean', mean), ('std', std), ('error', error)):\n\
         \x20   print(name, ' '.join(repr(x) for x in a))\n"
    );
    let out = match Command::new("python3")
        .arg("-c")
        .arg(&script)
        .arg(&path)
        .output()
    {
        Ok(out) => out,
        Err(e) => {
            println!("python3 not available ({e}): the reference reader was not run");
            return;
        }
    };
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let line = |name: &str| -> Vec<f64> {
        let l = text
            .lines()
            .find_map(|l| l.strip_prefix(&format!("{name} ")))
            .unwrap();
        l.split_whitespace().map(|x| x.parse().unwrap()).collect()
    };
    let a = law.axes();
    assert_eq!(line("p"), a.pressure);
    assert_eq!(line("h"), a.flux);
    assert_eq!(line("t"), a.contact_temperature);
    assert_eq!(line("mean"), law.jump_mean());
    assert_eq!(line("std"), law.jump_std());
    assert_eq!(line("error"), law.jump_error());
    assert!(text.contains("error_key estimated"), "{text}");
    assert!(text.contains("statistic ensemble_mean") && text.contains("flux_policy linear"));
}
