//! Tests of `user`: the CPU checks of a user's GLSL file.

use super::*;

const TORUS: &str = "// u: 0 2pi\n// v: 0 tau\nvec3 f(float u, float v) {\n    return vec3((1.0 + 0.3 * cos(v)) * cos(u), (1.0 + 0.3 * cos(v)) * sin(u), 0.3 * sin(v));\n}\n";

#[test]
fn reads_ranges_and_signature() {
    let f = UserFunction::from_text("torus.glsl", TORUS, None, None).unwrap();
    assert_eq!(f.domain.u, [0.0, std::f32::consts::TAU]);
    let f = UserFunction::from_text("torus.glsl", TORUS, Some([0.0, 1.0]), None).unwrap();
    assert_eq!(f.domain.u, [0.0, 1.0]);
    assert_eq!(parse_end("0.5*pi"), Some(std::f32::consts::FRAC_PI_2));
    assert_eq!(parse_end("-pi"), Some(-std::f32::consts::PI));
    assert_eq!(parse_end("x"), None);
}

#[test]
fn refuses_bad_files_by_name_and_line() {
    let cases = [
        (
            "vec3 g(float u, float v) { return vec3(u); }\n",
            "no function",
        ),
        (
            "// u: 0 1\n// v: 0 1\nvec3 f(float u) { return vec3(u); }\n",
            "line 3",
        ),
        (
            "// u: 0 1\n// v: 0 1\nfloat f(float u, float v) { return u; }\n",
            "found `float f",
        ),
        (
            "// u: 0 1\nvec3 f(float u, float v) { return vec3(u); }\n",
            "no range for v",
        ),
        (
            "// u: 0 one\n// v: 0 1\nvec3 f(float u, float v) { return vec3(u); }\n",
            "line 1",
        ),
        (
            "// u: 1 1\n// v: 0 1\nvec3 f(float u, float v) { return vec3(u); }\n",
            "surf.glsl",
        ),
    ];
    for (text, expected) in cases {
        let err = UserFunction::from_text("surf.glsl", text, None, None)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("surf.glsl") && err.contains(expected),
            "{text:?}: {err}"
        );
    }
    // A commented-out definition does not count.
    let err = UserFunction::from_text("s.glsl", "// vec3 f(float u, float v)\n", None, None)
        .unwrap_err()
        .to_string();
    assert!(err.contains("no function"), "{err}");
}

/// Block comments keep their lines, so the line a wrong definition is reported on is the
/// file's; a call of `f` (no type before it) is no definition.
#[test]
fn comments_and_calls() {
    let text = "/* a\n b */ vec3 g(float u) { return f(u, u); }\nfloat f(float u) { return u; }\n";
    let err = check_signature(text).unwrap_err();
    assert!(
        err.starts_with("line 3:") && err.contains("found `float f(float u)`"),
        "{err}"
    );
    assert_eq!(strip_comments("a /* x\ny */ b // c\nd"), "a \n b \nd");
    let tokens = tokenize("vec3 f(float u,\n 1.5)");
    let words: Vec<&str> = tokens.iter().map(|t| t.0.as_str()).collect();
    assert_eq!(words, ["vec3", "f", "(", "float", "u", ",", "1.5", ")"]);
    assert_eq!(tokens[6].1, 2);
    let err = check_signature("vec3 f(float u").unwrap_err();
    assert!(err.contains("unfinished"), "{err}");
}

/// Range lines: both ends needed, `tau` and multiples of `pi` read, the last line wins.
#[test]
fn range_lines() {
    let (u, v) = ranges("// u: -pi 2*pi\n//v: 0 1\n// v: 0 tau\n").unwrap();
    assert_eq!(u, Some([-std::f32::consts::PI, std::f32::consts::TAU]));
    assert_eq!(v, Some([0.0, std::f32::consts::TAU]));
    assert!(ranges("// u: 0\n").unwrap_err().contains("line 1"));
    assert_eq!(ranges("// w: 0 1\n").unwrap(), (None, None));
    assert_eq!(parse_end("1e40"), None);
    assert_eq!(parse_end(" 2PI "), Some(std::f32::consts::TAU));
}

/// `load` names the file when it is missing and reads it when it is there.
#[test]
fn load_names_the_file() {
    let path = crate::test_files::test_path("torus.glsl");
    let err = UserFunction::load(&path, None, None)
        .unwrap_err()
        .to_string();
    assert!(err.contains("torus.glsl"), "{err}");
    std::fs::write(&path, TORUS).unwrap();
    let f = UserFunction::load(&path, None, Some([-1.0, 1.0])).unwrap();
    assert_eq!((f.domain.v, f.text.as_str()), ([-1.0, 1.0], TORUS));
    assert_eq!(f.name, path.display().to_string());
}
