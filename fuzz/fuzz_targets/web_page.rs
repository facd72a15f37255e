//! What the demo page hands the engine (`tamias2d-web`): a scene JSON file
//! the user opened, then pointer presses, drags and drops at any `f64`
//! (NaN, infinities, far outside the world), steps, and frame snapshot
//! saves and loads. Never panics (a panic in wasm traps and stops the
//! page); every error is a message.
#![no_main]
use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use tamias2d::Real;
use tamias2d_web::play::{point, DropKind, Play};

#[derive(Arbitrary, Debug)]
enum Op {
    Step(u8),
    DragBegin { x: f64, y: f64, reach: f64 },
    DragMove { x: f64, y: f64 },
    DragEnd,
    Drop { ball: bool, x: f64, y: f64 },
    Save,
    Load,
}

#[derive(Arbitrary, Debug)]
struct Input {
    /// Scene JSON; when it is not a scene, the page's small fallback.
    json: String,
    ops: Vec<Op>,
}

/// Scenes above this many bodies are skipped: building them is slow, not
/// wrong, and the fuzzer's time is better spent elsewhere.
const MAX_BODIES: usize = 64;

fuzz_target!(|input: Input| {
    let desc = serde_json::from_str::<tamias2d_scenes::SceneDesc>(&input.json)
        .ok()
        .filter(|d| d.total_bodies() <= MAX_BODIES)
        .or_else(|| tamias2d_scenes::builtin("stack_10"));
    let Some(desc) = desc else { return };
    let Ok(mut play) = Play::new(&desc) else { return };
    for op in input.ops.iter().take(64) {
        // Every call returns a Result; the fuzzer looks for panics only.
        let _ = match *op {
            Op::Step(n) => play.step(u32::from(n % 4)),
            Op::DragBegin { x, y, reach } => point(x, y).and_then(|at| {
                let reach = Real::from_f64(reach).map_err(|e| e.to_string())?;
                play.drag_begin(at, reach).map(|_| ())
            }),
            Op::DragMove { x, y } => point(x, y).map(|at| play.drag_move(at)),
            Op::DragEnd => play.drag_end(),
            Op::Drop { ball, x, y } => {
                let kind = if ball { DropKind::Ball } else { DropKind::Box };
                point(x, y).and_then(|at| play.drop_body(kind, at).map(|_| ()))
            }
            Op::Save => {
                play.save();
                Ok(())
            }
            Op::Load => play.load(),
        };
    }
});
