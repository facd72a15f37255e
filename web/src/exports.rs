//! The functions the page calls: a C ABI over one state, no generator.
//!
//! Conventions (mirrored by `web/static/tamias.js`):
//! - Numbers in, numbers out: `u32`/`i32` for counts and indices, `f64` for
//!   pointer positions in world units.
//! - Text out (JSON, hex checksums, error messages) goes to one byte
//!   buffer, read at [`tamias_out_ptr`] for [`tamias_out_len`] bytes.
//! - Text in (a scene JSON) is written by the page into the buffer that
//!   [`tamias_in_reserve`] sizes and returns.
//! - A call that can fail returns a non-negative value on success and `-1`
//!   on failure, with the message (UTF-8) in the out buffer. Nothing here
//!   panics: a panic in wasm would trap and stop the page.
//!
//! `#[no_mangle]` is why this module allows `unsafe_code`: the lint counts
//! the attribute (two exports of one name would clash at link time). There
//! is no `unsafe` block: the page, not Rust, reads and writes the buffers
//! through the returned addresses, and only between calls.
#![allow(unsafe_code)]

use std::cell::RefCell;

use tamias2d::Real;
use tamias2d_scenes::REGISTRY;

use crate::draw::{transforms, DrawList};
use crate::golden;
use crate::lockstep::Lockstep;
use crate::play::{point, DropKind, Play};

/// Everything the page has built.
#[derive(Default)]
struct State {
    play: Option<Play>,
    lockstep: Option<Lockstep>,
    draw: DrawList,
    out: Vec<u8>,
    input: Vec<u8>,
}

thread_local! {
    static STATE: RefCell<State> = RefCell::new(State::default());
}

/// Runs `f` on the state; `-1` if it is already borrowed (a re-entrant
/// call, which the page never makes).
fn with(f: impl FnOnce(&mut State) -> i32) -> i32 {
    STATE.with(|s| s.try_borrow_mut().map_or(-1, |mut s| f(&mut s)))
}

/// A length or count as the `i32` the page reads (saturating: nothing
/// here comes near 2³¹).
fn count(n: usize) -> i32 {
    i32::try_from(n).unwrap_or(i32::MAX)
}

impl State {
    fn say(&mut self, text: &str) -> i32 {
        self.out.clear();
        self.out.extend_from_slice(text.as_bytes());
        count(self.out.len())
    }

    /// `Ok(n)` → `n`; `Err(m)` → `-1` with `m` in the out buffer.
    fn answer(&mut self, r: Result<i32, String>) -> i32 {
        r.unwrap_or_else(|e| {
            self.say(&e);
            -1
        })
    }

    fn play(&mut self) -> Result<&mut Play, String> {
        self.play.as_mut().ok_or_else(|| "no scene loaded".into())
    }

    fn lockstep(&mut self) -> Result<&mut Lockstep, String> {
        self.lockstep
            .as_mut()
            .ok_or_else(|| "no lockstep game started".into())
    }
}

/// Address of the out buffer.
#[no_mangle]
pub extern "C" fn tamias_out_ptr() -> *const u8 {
    STATE.with(|s| s.try_borrow().map_or(core::ptr::null(), |s| s.out.as_ptr()))
}

/// Length of the out buffer.
#[no_mangle]
pub extern "C" fn tamias_out_len() -> i32 {
    with(|s| count(s.out.len()))
}

/// Sizes the in buffer to `len` zero bytes and returns its address, for
/// the page to write into before a call that reads it.
#[no_mangle]
pub extern "C" fn tamias_in_reserve(len: u32) -> *mut u8 {
    STATE.with(|s| {
        s.try_borrow_mut().map_or(core::ptr::null_mut(), |mut s| {
            s.input.clear();
            s.input.resize(usize::try_from(len).unwrap_or(0), 0);
            s.input.as_mut_ptr()
        })
    })
}

/// Address of the draw list filled by the last `*_draw` call (`f32`s).
#[no_mangle]
pub extern "C" fn tamias_draw_ptr() -> *const f32 {
    STATE.with(|s| {
        s.try_borrow()
            .map_or(core::ptr::null(), |s| s.draw.floats.as_ptr())
    })
}

/// The built-in scenes as JSON, in registry order:
/// `[{"name","section","about","bodies"}, …]`.
#[no_mangle]
pub extern "C" fn tamias_scene_catalog() -> i32 {
    let list: Vec<_> = REGISTRY
        .iter()
        .map(|s| {
            serde_json::json!({
                "name": s.name,
                "section": s.section.letter().to_string(),
                "about": s.about,
                "bodies": s.bodies,
            })
        })
        .collect();
    let json = serde_json::Value::Array(list).to_string();
    with(|s| s.say(&json))
}

/// Builds built-in scene `index` (registry order) as the playground.
#[no_mangle]
pub extern "C" fn tamias_play_builtin(index: u32) -> i32 {
    with(|s| {
        let r = usize::try_from(index)
            .ok()
            .and_then(|i| REGISTRY.get(i))
            .ok_or_else(|| format!("no scene {index}"))
            .and_then(|info| Play::builtin(info.name));
        let r = r.map(|p| {
            s.play = Some(p);
            0
        });
        s.answer(r)
    })
}

/// Builds the scene JSON in the in buffer as the playground.
#[no_mangle]
pub extern "C" fn tamias_play_json() -> i32 {
    with(|s| {
        let r = core::str::from_utf8(&s.input)
            .map_err(|e| format!("scene file is not UTF-8: {e}"))
            .and_then(Play::from_json)
            .map(|p| {
                s.play = Some(p);
                0
            });
        s.answer(r)
    })
}

/// `n` steps of the playground.
#[no_mangle]
pub extern "C" fn tamias_play_step(n: u32) -> i32 {
    with(|s| {
        let r = s.play().and_then(|p| p.step(n)).map(|()| 0);
        s.answer(r)
    })
}

/// The playground's checksum and facts, as JSON in the out buffer:
/// `{"name","steps","bodies","checksum":"0x…"}`.
#[no_mangle]
pub extern "C" fn tamias_play_status() -> i32 {
    with(|s| {
        let r = s.play().map(|p| {
            serde_json::json!({
                "name": p.name,
                "steps": p.world.steps_taken(),
                "bodies": p.world.space.bodies().count(),
                "checksum": format!("{:#018x}", p.world.space.checksum()),
                "solver": solver_name(&p.world.space.settings().solver),
                "dragging": p.dragging(),
            })
            .to_string()
        });
        let r = r.map(|json| s.say(&json));
        s.answer(r)
    })
}

/// The status's name of a solver: `sequential`, `soft` or `soft narrow`.
fn solver_name(solver: &tamias2d::space::Solver) -> &'static str {
    match solver {
        tamias2d::space::Solver::Soft(soft)
            if soft.contact_precision == tamias2d::space::ContactPrecision::Narrow =>
        {
            "soft narrow"
        }
        tamias2d::space::Solver::Soft(_) => "soft",
        _ => "sequential",
    }
}

/// Switches the playground's solver: sequential impulses (`mode` 0), the
/// soft step scaled to the scene's gravity (1), or that soft step on the
/// narrow contact kernels (2, `ContactPrecision::Narrow`); any other
/// mode is an error.
#[no_mangle]
pub extern "C" fn tamias_play_solver(mode: u32) -> i32 {
    with(|s| {
        let r = s.play().and_then(|p| {
            let space = &mut p.world.space;
            let solver = match mode {
                0 => tamias2d::space::Solver::Sequential,
                1 | 2 => {
                    let mut soft = tamias2d_scenes::soft_step_for(space.settings().gravity);
                    if mode == 2 {
                        soft.contact_precision = tamias2d::space::ContactPrecision::Narrow;
                    }
                    tamias2d::space::Solver::Soft(soft)
                }
                _ => return Err(format!("solver mode {mode}: 0, 1 or 2 expected")),
            };
            let settings = tamias2d::space::Settings {
                solver,
                ..*space.settings()
            };
            space.set_settings(settings).map_err(|e| e.to_string())
        });
        s.answer(r.map(|()| 0))
    })
}

/// Fills the draw list with the playground (contact points if `contacts`
/// is non-zero); returns its length in floats.
#[no_mangle]
pub extern "C" fn tamias_play_draw(contacts: u32) -> i32 {
    with(|s| {
        let State { play, draw, .. } = s;
        let Some(play) = play.as_ref() else {
            s.say("no scene loaded");
            return -1;
        };
        draw.fill(&play.world.space, contacts != 0);
        count(draw.floats.len())
    })
}

/// Fills the draw buffer with every body's transform (`x, y, cos θ,
/// sin θ`, slot order; see [`crate::draw::transforms`]); returns its length
/// in floats.
#[no_mangle]
pub extern "C" fn tamias_play_transforms() -> i32 {
    with(|s| {
        let State { play, draw, .. } = s;
        let Some(play) = play.as_ref() else {
            s.say("no scene loaded");
            return -1;
        };
        transforms(&play.world.space, &mut draw.floats);
        count(draw.floats.len())
    })
}

/// Starts dragging the dynamic body within `reach` of `(x, y)`: 1 if one
/// was grabbed, 0 if none is there.
#[no_mangle]
pub extern "C" fn tamias_drag_begin(x: f64, y: f64, reach: f64) -> i32 {
    with(|s| {
        let r = point(x, y).and_then(|at| {
            let reach = Real::from_f64(reach).map_err(|e| format!("reach {reach}: {e}"))?;
            s.play()?.drag_begin(at, reach).map(i32::from)
        });
        s.answer(r)
    })
}

/// Moves the drag point.
#[no_mangle]
pub extern "C" fn tamias_drag_move(x: f64, y: f64) -> i32 {
    with(|s| {
        let r = point(x, y).and_then(|at| {
            s.play()?.drag_move(at);
            Ok(0)
        });
        s.answer(r)
    })
}

/// Ends the drag.
#[no_mangle]
pub extern "C" fn tamias_drag_end() -> i32 {
    with(|s| {
        let r = s.play().and_then(Play::drag_end).map(|()| 0);
        s.answer(r)
    })
}

/// Drops a ball (`kind` 0) or a box (1) at `(x, y)`.
#[no_mangle]
pub extern "C" fn tamias_drop(kind: u32, x: f64, y: f64) -> i32 {
    with(|s| {
        let kind = if kind == 0 {
            DropKind::Ball
        } else {
            DropKind::Box
        };
        let r = point(x, y).and_then(|at| s.play()?.drop_body(kind, at).map(|_| 0));
        s.answer(r)
    })
}

/// Saves the playground's frame snapshot; returns its size in bytes.
#[no_mangle]
pub extern "C" fn tamias_save() -> i32 {
    with(|s| {
        let r = s.play().map(|p| count(p.save()));
        s.answer(r)
    })
}

/// Loads the saved frame snapshot back into the playground.
#[no_mangle]
pub extern "C" fn tamias_load() -> i32 {
    with(|s| {
        let r = s.play().and_then(Play::load).map(|()| 0);
        s.answer(r)
    })
}

/// Number of golden checks (scenes times solvers).
#[no_mangle]
pub extern "C" fn tamias_golden_count() -> i32 {
    count(golden::count())
}

/// Runs golden check `index`; its outcome as JSON in the out buffer (see
/// [`golden::Outcome::to_json`]).
#[no_mangle]
pub extern "C" fn tamias_golden_run(index: u32) -> i32 {
    with(|s| {
        let r = usize::try_from(index)
            .map_err(|e| e.to_string())
            .and_then(golden::run)
            .map(|o| o.to_json());
        let r = r.map(|json| s.say(&json));
        s.answer(r)
    })
}

/// Starts a lockstep game of built-in scene `index`, peer B `delay` frames
/// behind.
#[no_mangle]
pub extern "C" fn tamias_lockstep_new(index: u32, delay: u32) -> i32 {
    with(|s| {
        let r = usize::try_from(index)
            .ok()
            .and_then(|i| REGISTRY.get(i))
            .ok_or_else(|| format!("no scene {index}"))
            .and_then(|info| Lockstep::new(info.name, delay))
            .map(|g| {
                s.lockstep = Some(g);
                0
            });
        s.answer(r)
    })
}

/// Peer A's frame; `has_input` non-zero means "drop a ball at (x, y)".
#[no_mangle]
pub extern "C" fn tamias_lockstep_a(has_input: u32, x: f64, y: f64) -> i32 {
    with(|s| {
        let r = (if has_input != 0 {
            point(x, y).map(Some)
        } else {
            Ok(None)
        })
        .and_then(|input| s.lockstep()?.advance_a(input))
        .map(|()| 0);
        s.answer(r)
    })
}

/// Peer B's frame; returns the frames it replayed (0: no rollback).
#[no_mangle]
pub extern "C" fn tamias_lockstep_b() -> i32 {
    with(|s| {
        let r = s
            .lockstep()
            .and_then(Lockstep::advance_b)
            .map(|n| i32::try_from(n).unwrap_or(i32::MAX));
        s.answer(r)
    })
}

/// The lockstep status as JSON in the out buffer (see
/// [`Lockstep::status_json`]).
#[no_mangle]
pub extern "C" fn tamias_lockstep_status() -> i32 {
    with(|s| {
        let r = s.lockstep().map(|g| g.status_json());
        let r = r.map(|json| s.say(&json));
        s.answer(r)
    })
}

/// Fills the draw list with peer A (`peer` 0) or B (1).
#[no_mangle]
pub extern "C" fn tamias_lockstep_draw(peer: u32, contacts: u32) -> i32 {
    with(|s| {
        let State { lockstep, draw, .. } = s;
        let Some(game) = lockstep.as_ref() else {
            s.say("no lockstep game started");
            return -1;
        };
        draw.fill(game.space(peer != 0), contacts != 0);
        count(draw.floats.len())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn out() -> String {
        STATE.with(|s| String::from_utf8_lossy(&s.borrow().out).into_owned())
    }

    #[test]
    fn the_page_calls_in_order() {
        assert!(tamias_scene_catalog() > 0);
        assert!(out().contains("\"pyramid_20\""));
        // Calls before a scene exists are errors with a message.
        assert_eq!(tamias_play_step(1), -1);
        assert_eq!(out(), "no scene loaded");
        assert_eq!(tamias_play_draw(0), -1);
        let index = REGISTRY.iter().position(|s| s.name == "pyramid_20");
        let index = index.and_then(|i| u32::try_from(i).ok()).unwrap_or(0);
        assert_eq!(tamias_play_builtin(index), 0);
        assert_eq!(tamias_play_step(2), 0);
        assert!(tamias_play_draw(1) > 0);
        assert!(!tamias_draw_ptr().is_null());
        // pyramid_20: the ground and 210 boxes, 4 floats each.
        assert_eq!(tamias_play_transforms(), 211 * 4);
        assert!(tamias_play_status() > 0);
        assert!(out().contains("\"steps\":2"), "{}", out());
        assert!(out().contains("\"solver\":\"sequential\""), "{}", out());
        // The solver switch, both ways.
        assert_eq!(tamias_play_solver(1), 0);
        assert_eq!(tamias_play_step(2), 0);
        assert!(tamias_play_status() > 0);
        assert!(out().contains("\"solver\":\"soft\""), "{}", out());
        assert_eq!(tamias_play_solver(2), 0);
        assert_eq!(tamias_play_step(2), 0);
        assert!(tamias_play_status() > 0);
        assert!(out().contains("\"solver\":\"soft narrow\""), "{}", out());
        assert_eq!(tamias_play_solver(3), -1);
        assert!(out().contains("solver mode 3"), "{}", out());
        assert_eq!(tamias_play_solver(0), 0);
        assert_eq!(tamias_drop(1, 0.0, 50.0), 0);
        assert_eq!(tamias_drop(0, f64::NAN, 50.0), -1);
        assert!(tamias_save() > 0);
        assert_eq!(tamias_load(), 0);
        assert_eq!(tamias_play_builtin(u32::MAX), -1);
        assert!(out().contains("no scene"));
        // Bad scene JSON.
        let ptr = tamias_in_reserve(3);
        assert!(!ptr.is_null());
        assert_eq!(tamias_play_json(), -1);
        assert!(out().contains("invalid scene JSON"), "{}", out());
        // Lockstep.
        assert_eq!(tamias_lockstep_b(), -1);
        assert_eq!(tamias_lockstep_new(index, 3), 0);
        assert_eq!(tamias_lockstep_a(1, 0.0, 60.0), 0);
        assert_eq!(tamias_lockstep_b(), 0);
        assert!(tamias_lockstep_draw(1, 0) > 0);
        assert!(tamias_lockstep_status() > 0);
        assert!(out().contains("\"frame\":1"), "{}", out());
        assert!(tamias_golden_count() > 10);
        assert_eq!(tamias_golden_run(u32::MAX), -1);
    }
}
