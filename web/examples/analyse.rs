//! The page's analysis of one program, natively, timed: `analyse FILE CONTROLLER [RUNS]` runs
//! `api::analyse` with the request the page sends (no motions, no blanks, the first 20 pass
//! tables, 1,000 lines of G-code, 500 rows a table) RUNS times (default 3) and prints each run's
//! time and the size of its JSON. The pastes of issue 28: `scripts/pastes.py DIR`
//! (docs/performance.md).
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (Some(file), Some(controller)) = (args.get(1), args.get(2)) else {
        eprintln!("usage: analyse FILE CONTROLLER [RUNS]");
        std::process::exit(2);
    };
    let runs: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(3);
    let program = match std::fs::read_to_string(file) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("{file}: {e}");
            std::process::exit(1);
        }
    };
    let request = serde_json::json!({
        "controller": controller, "program": program, "motions": false, "blanks": false,
        "max_cycles": 20, "gcode_lines": 1000, "max_passes": 500,
    })
    .to_string();
    for _ in 0..runs {
        let t = Instant::now();
        let json = threadcut_web::api::analyse(&request).to_string();
        println!(
            "{file}: analysed in {:.1} ms, {} bytes of JSON",
            t.elapsed().as_secs_f64() * 1e3,
            json.len()
        );
    }
}
