//! `threadcut plot`: the SVG text is snapshotted (it is deterministic), and rendered to PNG with
//! resvg so that a person can look at it (`target/tmp/plot-*.png`).

use std::path::PathBuf;
use std::process::Command;

const RADIAL: &str =
    "G00 X80 Z10\nG97 S600 M03\nG78 P010060 Q0.1 R0.05\nG78 X60 Z-30 P1.2 Q0.4 F2\n";
/// Left/right alternating infeed (r = 04), a 2.5 mm lead, finishing at the last rough position.
const ALTERNATING: &str =
    "G00 X52 Z5\nG97 S400 M03\nG78 P010460 Q0.08 R0.05\nG78 X43.3 Z-25 P1.55 Q0.45 F2.5\n";

fn tmp(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name)
}

fn plot(name: &str, src: &str, extra: &[&str]) -> String {
    let input = tmp(&format!("plot-{name}.nc"));
    std::fs::write(&input, src).unwrap();
    let out = tmp(&format!("plot-{name}.svg"));
    let status = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(["plot", input.to_str().unwrap(), "-c", "gsk980", "-o"])
        .arg(&out)
        .args(extra)
        .status()
        .unwrap();
    assert!(status.success());
    std::fs::read_to_string(&out).unwrap()
}

/// Renders the SVG with DejaVu Sans (the font the SVG names) and returns the pixmap, also saved
/// as PNG beside the SVG.
fn render(name: &str, svg: &str) -> resvg::tiny_skia::Pixmap {
    let mut opt = resvg::usvg::Options::default();
    let font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
    let data = std::fs::read(font).expect("fonts-dejavu-core provides DejaVuSans.ttf");
    opt.fontdb_mut().load_font_data(data);
    let bold = "/usr/share/fonts/truetype/dejavu/DejaVuSans-Bold.ttf";
    if let Ok(data) = std::fs::read(bold) {
        opt.fontdb_mut().load_font_data(data);
    }
    let tree = resvg::usvg::Tree::from_str(svg, &opt).expect("the SVG parses");
    let size = tree.size().to_int_size();
    let mut pixmap = resvg::tiny_skia::Pixmap::new(size.width(), size.height()).unwrap();
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::default(),
        &mut pixmap.as_mut(),
    );
    pixmap.save_png(tmp(&format!("plot-{name}.png"))).unwrap();
    pixmap
}

/// Dark pixels (text, strokes) inside a rectangle of the picture.
fn ink(p: &resvg::tiny_skia::Pixmap, x0: u32, y0: u32, x1: u32, y1: u32) -> usize {
    let mut n = 0;
    for y in y0..y1.min(p.height()) {
        for x in x0..x1.min(p.width()) {
            let c = p.pixel(x, y).unwrap();
            if u32::from(c.red()) + u32::from(c.green()) + u32::from(c.blue()) < 300 {
                n += 1;
            }
        }
    }
    n
}

#[test]
fn radial_plot_snapshot() {
    let svg = plot("radial", RADIAL, &[]);
    render("radial", &svg);
    insta::assert_snapshot!("radial_svg", svg);
}

#[test]
fn alternating_plot_with_nose_radius_snapshot() {
    let svg = plot("alternating", ALTERNATING, &["--nose-radius", "0.1"]);
    insta::assert_snapshot!("alternating_svg", svg);
}

#[test]
fn plots_are_deterministic_and_structured() {
    let a = plot("det-a", RADIAL, &[]);
    let b = plot("det-b", RADIAL, &[]);
    assert_eq!(a, b);
    // Nine passes: nine chips, nine tool outlines (plus the target), nine legend rows.
    assert_eq!(
        a.matches("fill-opacity=\"0.55\"").count(),
        9,
        "eight rough chips and the finishing pass that removes the allowance"
    );
    assert_eq!(a.matches("<polyline").count(), 10);
    // Each pass: a dashed rapid in, a bold thread move, two rapids out.
    assert_eq!(a.matches("stroke-width=\"2.4\"").count(), 9);
    // The last retract ends at the start point: no separate return move.
    assert_eq!(a.matches("stroke-dasharray=\"4 3\"").count(), 9 * 3);
    assert_eq!(
        a.matches(r#"width="10" height="10""#).count(),
        9,
        "nine legend rows"
    );
}

#[test]
fn the_png_is_legible() {
    let svg = plot("png", ALTERNATING, &["--nose-radius", "0.1"]);
    let p = render("alternating", &svg);
    assert_eq!((p.width(), p.height()), (1100, 480));
    // The title line has text in it.
    assert!(
        ink(&p, 20, 8, 700, 30) > 500,
        "title: {}",
        ink(&p, 20, 8, 700, 30)
    );
    // The section panel, the legend and the toolpath panel all have ink.
    assert!(ink(&p, 21, 60, 439, 400) > 500);
    assert!(ink(&p, 455, 60, 640, 400) > 500);
    assert!(ink(&p, 651, 60, 1079, 400) > 300);
}

#[test]
fn a_program_without_cycles_gives_a_note() {
    let svg = plot("empty", "G00 X10 Z10\n", &[]);
    assert!(svg.contains("no thread in this program"));
    render("empty", &svg);
}

#[test]
fn several_cycles_stack_into_rows() {
    // An internal thread, a tapered one with a tail-out, and an inch thread in one program.
    let src = "G00 X20 Z5\nG97 S500\nG78 P020460 Q0.1 R0.05\nG78 X26 Z-20 P1.0 Q0.3 F1.5\n\
               G00 X80 Z10\nG78 P010060\nG78 X60 Z-30 R-2 P1.2 Q0.4 F2 J1 K2\n\
               G20\nG00 X3 Z0.5\nG78 X2.5 Z-1 P0.04 Q0.01 I16\n";
    let svg = plot("multi", src, &["--tip-flat", "0.05"]);
    assert_eq!(svg.matches("Pass diagram").count(), 3);
    assert!(svg.contains("height=\"1420\""));
    assert!(
        svg.contains("in²"),
        "the inch cycle's legend is in square inches"
    );
    let p = render("multi", &svg);
    for row in 0..3 {
        let y = 470 * row;
        assert!(ink(&p, 21, y + 60, 439, y + 400) > 300, "row {row}");
        assert!(ink(&p, 651, y + 60, 1079, y + 400) > 300, "row {row}");
    }
}
