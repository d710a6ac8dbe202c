//! threadcut in the browser: a JSON-in, JSON-out API over the `threadcut` library for the static
//! page in `web/www/`. Every function takes and returns JSON text; errors are values
//! (`{"ok": false, …}`), never exceptions.

pub mod api;
pub mod forms;

use wasm_bindgen::prelude::*;

/// `{"ok": true, "controllers": [{name, description, units, diameter_x, form}]}`.
#[wasm_bindgen]
pub fn controllers() -> String {
    api::controllers().to_string()
}

/// A standard thread by name (`M20x2.5`, `1/2-13 UNC-2A`).
#[wasm_bindgen]
pub fn thread(name: &str) -> String {
    api::thread(name).to_string()
}

/// `{"controller", "thread", "internal"}` → the form's values for that thread.
#[wasm_bindgen]
pub fn fill(request: &str) -> String {
    api::fill(request).to_string()
}

/// `{"controller", "values": {field: text}}` → the generated program, analysed.
#[wasm_bindgen]
pub fn plan(request: &str) -> String {
    api::plan(request).to_string()
}

/// `{"from", "to", "program"}` → the program converted for `to`, or the block that cannot be.
#[wasm_bindgen]
pub fn convert(request: &str) -> String {
    api::convert(request).to_string()
}

/// `{"controller", "program"}` → the whole expanded program (`{ok, gcode}`).
#[wasm_bindgen]
pub fn expand(request: &str) -> String {
    api::expand(request).to_string()
}

/// `{"controller", "program"}` → the program analysed: passes, G-code, motions, plots, diagnostics.
#[wasm_bindgen]
pub fn analyse(request: &str) -> String {
    api::analyse(request).to_string()
}
