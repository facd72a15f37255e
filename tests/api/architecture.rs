//! The engine's floor plan, checked against its code.
//!
//! `docs/architecture.md` lists the engine's modules in layers ("Modules and
//! the direction of their dependencies"). This test reads that table and the
//! `crate::` paths of every library source file (outside test code), and
//! fails when a module names one of its own layer or a higher one, when a
//! module is missing from the table, or when source files import each other
//! in a circle. So the documented order is the real one.
use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The layer table of `docs/architecture.md`: module name → layer.
fn documented_layers() -> BTreeMap<String, u32> {
    let doc = fs::read_to_string(Path::new(ROOT).join("docs/architecture.md")).unwrap();
    let start = doc
        .find("## Modules and the direction of their dependencies")
        .expect("the architecture doc has its module section");
    let mut layers = BTreeMap::new();
    for line in doc[start..].lines().skip(1) {
        if line.starts_with("## ") {
            break;
        }
        let cells: Vec<&str> = line.split('|').map(str::trim).collect();
        let (Some(layer), Some(modules)) = (cells.get(1), cells.get(2)) else {
            continue;
        };
        let Ok(layer) = layer.parse::<u32>() else {
            continue;
        };
        for name in modules.split('`').skip(1).step_by(2) {
            layers.insert(name.to_string(), layer);
        }
    }
    assert!(!layers.is_empty(), "no layer table found");
    layers
}

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The module path of a source file: `src/space/step/mod.rs` → `space::step`.
fn module_of(file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(Path::new(ROOT).join("src")).unwrap();
    let mut parts: Vec<String> = rel
        .iter()
        .map(|c| c.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if matches!(parts.last().map(String::as_str), Some("mod" | "lib")) {
        parts.pop();
    }
    parts
}

/// The library code of a file: its lines up to its test module, without
/// comments (doc links may point anywhere), each `use` declaration joined
/// into one line and its braces expanded: `use a::{b, c::D};` becomes
/// `use a::b;` and `use a::c::D;`.
fn code_lines(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut pending: Option<String> = None;
    for line in text
        .lines()
        .take_while(|l| !l.starts_with("#[cfg(test)]"))
        .filter(|l| !l.trim_start().starts_with("//"))
    {
        let t = line.trim();
        let starts_use = ["use ", "pub use ", "pub(crate) use ", "pub(super) use "]
            .iter()
            .any(|p| t.starts_with(p));
        match pending.as_mut() {
            Some(p) => p.push_str(t),
            None if starts_use => pending = Some(t.to_string()),
            None => {
                out.push(line.to_string());
                continue;
            }
        }
        if t.ends_with(';') {
            out.extend(expand_use(&pending.take().unwrap_or_default()));
        }
    }
    out
}

/// `use a::{b, c::D};` as `use a::b;` and `use a::c::D;` (one level of
/// braces, as rustfmt writes them); other lines unchanged.
fn expand_use(stmt: &str) -> Vec<String> {
    let (Some(open), Some(close)) = (stmt.find('{'), stmt.rfind('}')) else {
        return vec![stmt.to_string()];
    };
    let (head, items) = (&stmt[..open], &stmt[open + 1..close]);
    items
        .split(',')
        .map(str::trim)
        .filter(|i| !i.is_empty())
        .map(|i| match i {
            "self" => format!("{};", head.trim_end_matches("::")),
            _ => format!("{head}{i};"),
        })
        .collect()
}

/// The paths a line names, each as module segments: `crate::a::b::C`,
/// `super::x::Y` (resolved against `module`), and `child::…` of a child
/// module the file declares.
fn named_paths(line: &str, module: &[String], children: &BTreeSet<String>) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let is_ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let segments = |rest: &str| -> Vec<String> {
        let mut segs = Vec::new();
        let mut s = rest;
        loop {
            let end = s.find(|c: char| !is_ident(c)).unwrap_or(s.len());
            if end == 0 {
                break;
            }
            segs.push(s[..end].to_string());
            match s[end..].strip_prefix("::") {
                Some(next) => s = next,
                None => break,
            }
        }
        segs
    };
    for (i, _) in line.match_indices("crate::") {
        if line[..i].ends_with(|c: char| is_ident(c)) || line[..i].ends_with("pub(in ") {
            continue; // `$crate::`, `tamias2d_crate::`, a visibility…
        }
        out.push(segments(&line[i + 7..]));
    }
    for (i, _) in line.match_indices("super::") {
        if line[..i].ends_with(|c: char| is_ident(c) || c == ':') {
            continue; // counted with the path it continues
        }
        let mut base: Vec<String> = module.to_vec();
        let mut rest = &line[i..];
        while let Some(r) = rest.strip_prefix("super::") {
            base.pop();
            rest = r;
        }
        base.extend(segments(rest));
        out.push(base);
    }
    for child in children {
        let at = format!("{child}::");
        for (i, _) in line.match_indices(&at) {
            if line[..i].ends_with(|c: char| is_ident(c) || c == ':') {
                continue; // a deeper path's segment
            }
            let mut full = module.to_vec();
            full.extend(segments(&line[i..]));
            out.push(full);
        }
    }
    out
}

/// The items a `pub use` line hands on: `pub use a::{B, C};` → B, C;
/// `pub use a::B as D;` → D.
fn reexported_items(line: &str) -> Vec<String> {
    let body = line.trim_end().trim_end_matches(';');
    let list = match (body.find('{'), body.rfind('}')) {
        (Some(a), Some(b)) if a < b => &body[a + 1..b],
        _ => body.rsplit("::").next().unwrap_or(""),
    };
    list.split(',')
        .filter_map(|item| item.split_whitespace().last())
        .filter(|w| w.chars().next().is_some_and(|c| c.is_ascii_alphabetic()))
        .map(str::to_string)
        .collect()
}

/// The source file a module path lands in: the longest prefix of `segs`
/// that is a file of `files` (module path → file index), followed through
/// that file's re-exports of the next name.
fn resolve(
    segs: &[String],
    files: &BTreeMap<Vec<String>, usize>,
    srcs: &[Source],
) -> Option<usize> {
    let n = (1..=segs.len())
        .rev()
        .find(|&n| files.contains_key(&segs[..n].to_vec()))?;
    let file = files[&segs[..n].to_vec()];
    match segs.get(n).and_then(|next| srcs[file].reexports.get(next)) {
        Some(origin) if origin.as_slice() != segs => resolve(origin, files, srcs).or(Some(file)),
        _ => Some(file),
    }
}

struct Source {
    path: PathBuf,
    module: Vec<String>,
    /// Module paths named by its library code.
    names: Vec<Vec<String>>,
    /// Its `pub use` re-exports: name → the module path it comes from (a
    /// name used through a re-export depends on where it is defined, not
    /// on the file that hands it on).
    reexports: BTreeMap<String, Vec<String>>,
}

fn sources() -> Vec<Source> {
    let mut files = Vec::new();
    rust_files(&Path::new(ROOT).join("src"), &mut files);
    files
        .into_iter()
        .filter(|p| p.file_name().is_some_and(|n| n != "tests.rs"))
        .map(|path| {
            let text = fs::read_to_string(&path).unwrap();
            let module = module_of(&path);
            let lines = code_lines(&text);
            let children: BTreeSet<String> = lines
                .iter()
                .map(String::as_str)
                .filter_map(|l| {
                    let l = l.trim_start();
                    let l = l
                        .strip_prefix("pub(crate) ")
                        .or(l.strip_prefix("pub "))
                        .unwrap_or(l);
                    l.strip_prefix("mod ")?
                        .strip_suffix(';')
                        .map(str::to_string)
                })
                .collect();
            let mut reexports = BTreeMap::new();
            let mut names = Vec::new();
            for l in lines.iter().map(String::as_str) {
                let found = named_paths(l, &module, &children);
                let t = l.trim_start();
                if t.starts_with("pub use ") || t.starts_with("pub(crate) use ") {
                    for path in &found {
                        for item in reexported_items(t) {
                            reexports.insert(item, path.clone());
                        }
                    }
                    continue;
                }
                names.extend(found.into_iter().filter(|s| !s.is_empty()));
            }
            // A name the file hands on and also uses itself is an import.
            let uses_word = |word: &str| {
                lines
                    .iter()
                    .filter(|l| !l.contains(" use ") && !l.starts_with("use "))
                    .any(|l| {
                        l.match_indices(word).any(|(i, _)| {
                            let before = l[..i].chars().next_back();
                            let after = l[i + word.len()..].chars().next();
                            let ident = |c: Option<char>| {
                                c.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_')
                            };
                            !ident(before) && !ident(after)
                        })
                    })
            };
            for (item, path) in &reexports {
                if uses_word(item) {
                    names.push(path.clone());
                }
            }
            Source {
                path,
                module,
                names,
                reexports,
            }
        })
        .collect()
}

#[test]
fn every_module_imports_only_from_layers_below_its_own() {
    let layers = documented_layers();
    let srcs = sources();
    let top_modules: BTreeSet<String> = srcs
        .iter()
        .filter_map(|s| s.module.first().cloned())
        .collect();
    let mut problems = Vec::new();
    for m in &top_modules {
        if !layers.contains_key(m) {
            problems.push(format!(
                "module `{m}` is not in docs/architecture.md's layer table"
            ));
        }
    }
    for s in &srcs {
        let Some(own) = s.module.first() else {
            continue; // lib.rs
        };
        let Some(&own_layer) = layers.get(own) else {
            continue;
        };
        for name in &s.names {
            let target = &name[0];
            if target == own || !top_modules.contains(target) {
                continue; // itself, or a macro or item at the crate root
            }
            let Some(&layer) = layers.get(target) else {
                continue;
            };
            if layer >= own_layer {
                problems.push(format!(
                    "{} (`{own}`, layer {own_layer}) names `{}` (layer {layer})",
                    s.path.strip_prefix(ROOT).unwrap().display(),
                    name.join("::"),
                ));
            }
        }
    }
    problems.sort();
    problems.dedup();
    assert!(
        problems.is_empty(),
        "against the layer order:\n{}",
        problems.join("\n")
    );
}

#[test]
fn no_source_files_import_each_other_in_a_circle() {
    let srcs = sources();
    let index: BTreeMap<Vec<String>, usize> = srcs
        .iter()
        .enumerate()
        .map(|(i, s)| (s.module.clone(), i))
        .collect();
    let edges: Vec<BTreeSet<usize>> = srcs
        .iter()
        .enumerate()
        .map(|(i, s)| {
            s.names
                .iter()
                .filter_map(|n| resolve(n, &index, &srcs))
                .filter(|&j| j != i)
                .collect()
        })
        .collect();
    // Strongly connected components (Tarjan), iteratively small enough.
    let n = srcs.len();
    let mut order = vec![usize::MAX; n];
    let mut low = vec![0; n];
    let mut on_stack = vec![false; n];
    let mut stack = Vec::new();
    let mut counter = 0;
    let mut circles = Vec::new();
    fn visit(
        v: usize,
        edges: &[BTreeSet<usize>],
        st: &mut (Vec<usize>, Vec<usize>, Vec<bool>, Vec<usize>, usize),
        circles: &mut Vec<Vec<usize>>,
    ) {
        st.0[v] = st.4;
        st.1[v] = st.4;
        st.4 += 1;
        st.3.push(v);
        st.2[v] = true;
        for &w in &edges[v] {
            if st.0[w] == usize::MAX {
                visit(w, edges, st, circles);
                st.1[v] = st.1[v].min(st.1[w]);
            } else if st.2[w] {
                st.1[v] = st.1[v].min(st.0[w]);
            }
        }
        if st.1[v] == st.0[v] {
            let mut comp = Vec::new();
            while let Some(w) = st.3.pop() {
                st.2[w] = false;
                comp.push(w);
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                circles.push(comp);
            }
        }
    }
    let mut st = (
        std::mem::take(&mut order),
        std::mem::take(&mut low),
        std::mem::take(&mut on_stack),
        std::mem::take(&mut stack),
        std::mem::take(&mut counter),
    );
    for v in 0..n {
        if st.0[v] == usize::MAX {
            visit(v, &edges, &mut st, &mut circles);
        }
    }
    let name = |i: usize| {
        srcs[i]
            .path
            .strip_prefix(ROOT)
            .unwrap()
            .display()
            .to_string()
    };
    let described: Vec<String> = circles
        .iter()
        .map(|c| {
            let mut arrows: Vec<String> = c
                .iter()
                .flat_map(|&i| {
                    edges[i]
                        .iter()
                        .filter(|j| c.contains(j))
                        .map(move |&j| format!("  {} -> {}", name(i), name(j)))
                })
                .collect();
            arrows.sort();
            format!("a circle of {} files:\n{}", c.len(), arrows.join("\n"))
        })
        .collect();
    assert!(
        described.is_empty(),
        "import circles:\n{}",
        described.join("\n")
    );
}

#[test]
fn the_step_table_lists_the_stages_in_run_order() {
    let doc = fs::read_to_string(Path::new(ROOT).join("docs/architecture.md")).unwrap();
    let start = doc
        .find("## The step")
        .expect("the architecture doc has its step section");
    let documented: Vec<&str> = doc[start..]
        .lines()
        .skip(1)
        .take_while(|l| !l.starts_with("## "))
        .filter_map(|l| l.strip_prefix("| **")?.split("**").next())
        .collect();
    let code: Vec<&str> = tamias2d::space::Stage::ALL
        .iter()
        .map(|s| s.name())
        .collect();
    assert_eq!(documented, code);
}
