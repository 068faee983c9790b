//! The props of an endless-world scene file: `[prop_materials.<name>]`, `[prop_kinds.<name>]`
//! and `[[prop_place]]` tables, read into a [`relief::props::Scene`] (docs/props.md gives the
//! format). A file without them keeps the shipped landscape's props; kinds given replace them.
//! Every node is read with its depth counted, so no file makes the reader recurse past
//! [`relief::props::MAX_DEPTH`]; the library validates the rest ([`Scene::compile`]).

use relief::error::{Error, Result};
use relief::props::place::Placed;
use relief::props::{kinds, Combine, Kind, Material, Node, Scene, Shape, Transform, MAX_DEPTH};

/// The scene-file tables this module reads.
pub const TABLES: [&str; 3] = ["prop_materials", "prop_kinds", "prop_place"];

fn invalid(key: &str, value: impl ToString, allowed: &str) -> Error {
    Error::invalid(key, value, allowed)
}

fn number(key: &str, v: &toml::Value) -> Result<f32> {
    match v {
        toml::Value::Float(x) => Ok(*x as f32),
        toml::Value::Integer(i) => Ok(*i as f32),
        other => Err(invalid(key, shown(other), "a number")),
    }
}

fn shown(v: &toml::Value) -> String {
    crate::shown::toml_shown(v)
}

fn number64(key: &str, v: &toml::Value) -> Result<f64> {
    match v {
        toml::Value::Float(x) => Ok(*x),
        toml::Value::Integer(i) => Ok(*i as f64),
        other => Err(invalid(key, shown(other), "a number")),
    }
}

fn triple(key: &str, v: &toml::Value) -> Result<[f32; 3]> {
    match v {
        toml::Value::Array(a) if a.len() == 3 => {
            let n = a
                .iter()
                .map(|x| number(key, x))
                .collect::<Result<Vec<_>>>()?;
            Ok([n[0], n[1], n[2]])
        }
        other => Err(invalid(key, shown(other), "[x, y, z], three numbers")),
    }
}

fn table<'a>(key: &str, v: &'a toml::Value) -> Result<&'a toml::Table> {
    v.as_table()
        .ok_or_else(|| invalid(key, shown(v), "a table"))
}

/// Refuses keys of `t` not in `allowed`.
fn only(key: &str, t: &toml::Table, allowed: &[&str]) -> Result<()> {
    match t.keys().find(|k| !allowed.contains(&k.as_str())) {
        Some(k) => Err(invalid(
            &format!("{key}.{k}"),
            "an unknown key",
            &allowed.join(", "),
        )),
        None => Ok(()),
    }
}

const SHAPES: [&str; 7] = [
    "sphere",
    "box",
    "round_box",
    "torus",
    "cylinder",
    "capsule",
    "plane",
];
const OPS: [&str; 6] = [
    "union",
    "intersection",
    "subtraction",
    "smooth_union",
    "smooth_intersection",
    "smooth_subtraction",
];
const NODE_KEYS: [&str; 5] = ["translate", "rotate", "scale", "material", "children"];

fn transform(key: &str, t: &toml::Table) -> Result<Transform> {
    let mut out = Transform::default();
    if let Some(v) = t.get("translate") {
        out.translate = triple(&format!("{key}.translate"), v)?;
    }
    if let Some(v) = t.get("rotate") {
        out.rotate = triple(&format!("{key}.rotate"), v)?;
    }
    if let Some(v) = t.get("scale") {
        let k = format!("{key}.scale");
        out.scale = match v {
            toml::Value::Array(_) => triple(&k, v)?,
            other => [number(&k, other)?; 3],
        };
    }
    Ok(out)
}

fn shape(key: &str, name: &str, v: &toml::Value) -> Result<Shape> {
    let t = table(key, v)?;
    let get = |k: &str| {
        t.get(k)
            .ok_or_else(|| invalid(&format!("{key}.{k}"), "missing", "a number"))
            .and_then(|v| number(&format!("{key}.{k}"), v))
    };
    let size = || {
        t.get("size")
            .ok_or_else(|| invalid(&format!("{key}.size"), "missing", "[x, y, z]"))
            .and_then(|v| triple(&format!("{key}.size"), v))
            .map(|s| s.map(|x| x / 2.0))
    };
    let (shape, keys): (Shape, &[&str]) = match name {
        "sphere" => (
            Shape::Sphere {
                radius: get("radius")?,
            },
            &["radius"],
        ),
        "box" => (Shape::Box { half: size()? }, &["size"]),
        "round_box" => (
            Shape::RoundBox {
                half: size()?,
                radius: get("radius")?,
            },
            &["size", "radius"],
        ),
        "torus" => (
            Shape::Torus {
                major: get("major")?,
                minor: get("minor")?,
            },
            &["major", "minor"],
        ),
        "cylinder" | "capsule" => {
            let (radius, half_height) = (get("radius")?, get("height")? / 2.0);
            let s = if name == "cylinder" {
                Shape::Cylinder {
                    radius,
                    half_height,
                }
            } else {
                Shape::Capsule {
                    radius,
                    half_height,
                }
            };
            (s, &["radius", "height"])
        }
        _ => (
            Shape::Plane {
                normal: t
                    .get("normal")
                    .ok_or_else(|| invalid(&format!("{key}.normal"), "missing", "[x, y, z]"))
                    .and_then(|v| triple(&format!("{key}.normal"), v))?,
                offset: t
                    .get("offset")
                    .map_or(Ok(0.0), |v| number(&format!("{key}.offset"), v))?,
            },
            &["normal", "offset"],
        ),
    };
    only(key, t, keys)?;
    Ok(shape)
}

struct Reader<'a> {
    materials: &'a [Material],
}

impl Reader<'_> {
    /// One node at `key`, `depth` deep: refused past [`MAX_DEPTH`] before reading its
    /// children.
    fn node(&self, key: &str, v: &toml::Value, depth: usize) -> Result<Node> {
        if depth > MAX_DEPTH {
            return Err(invalid(
                key,
                format!("a tree deeper than {MAX_DEPTH}"),
                &format!("at most {MAX_DEPTH} deep"),
            ));
        }
        let t = table(key, v)?;
        let what: Vec<&str> = t
            .keys()
            .map(String::as_str)
            .filter(|k| SHAPES.contains(k) || OPS.contains(k) || *k == "displace")
            .collect();
        let [what] = what[..] else {
            return Err(invalid(
                key,
                format!("{} shapes or operations", what.len()),
                "one of sphere, box, round_box, torus, cylinder, capsule, plane, union, \
                 intersection, subtraction, smooth_union, smooth_intersection, \
                 smooth_subtraction, displace",
            ));
        };
        let mut allowed = NODE_KEYS.to_vec();
        allowed.push(what);
        only(key, t, &allowed)?;
        let form = transform(key, t)?;
        let node = if SHAPES.contains(&what) {
            let material = match t.get("material") {
                None => 0,
                Some(toml::Value::String(name)) => self
                    .materials
                    .iter()
                    .position(|m| &m.name == name)
                    .ok_or_else(|| {
                        let names: Vec<&str> =
                            self.materials.iter().map(|m| m.name.as_str()).collect();
                        invalid(&format!("{key}.material"), name, &names.join(", "))
                    })? as u32,
                Some(other) => {
                    return Err(invalid(&format!("{key}.material"), shown(other), "a name"))
                }
            };
            Node::Shape {
                shape: shape(&format!("{key}.{what}"), what, &t[what])?,
                transform: Transform::default(),
                material,
            }
        } else if what == "displace" {
            let d = table(&format!("{key}.displace"), &t[what])?;
            only(
                &format!("{key}.displace"),
                d,
                &["amplitude", "frequency", "child"],
            )?;
            let get = |k: &str| {
                d.get(k)
                    .ok_or_else(|| invalid(&format!("{key}.displace.{k}"), "missing", "a number"))
                    .and_then(|v| number(&format!("{key}.displace.{k}"), v))
            };
            let child = d
                .get("child")
                .ok_or_else(|| invalid(&format!("{key}.displace.child"), "missing", "a node"))?;
            Node::Displace {
                amplitude: get("amplitude")?,
                frequency: get("frequency")?,
                child: Box::new(self.node(&format!("{key}.displace.child"), child, depth + 1)?),
            }
        } else {
            let op = match what.trim_start_matches("smooth_") {
                "union" => Combine::Union,
                "intersection" => Combine::Intersection,
                _ => Combine::Subtraction,
            };
            let smooth = if what.starts_with("smooth_") {
                Some(number(&format!("{key}.{what}"), &t[what])?)
            } else {
                match &t[what] {
                    toml::Value::Boolean(true) => None,
                    other => {
                        return Err(invalid(
                            &format!("{key}.{what}"),
                            shown(other),
                            "true (smooth_* take a radius)",
                        ))
                    }
                }
            };
            let children = match t.get("children") {
                Some(toml::Value::Array(a)) => a
                    .iter()
                    .enumerate()
                    .map(|(i, c)| self.node(&format!("{key}.children[{i}]"), c, depth + 1))
                    .collect::<Result<Vec<_>>>()?,
                other => {
                    return Err(invalid(
                        &format!("{key}.children"),
                        other.map_or("missing".into(), shown),
                        "an array of two or more nodes",
                    ))
                }
            };
            Node::Combine {
                op,
                smooth,
                children,
            }
        };
        if form == Transform::default() {
            return Ok(node);
        }
        Ok(match node {
            Node::Shape {
                shape, material, ..
            } => Node::Shape {
                shape,
                transform: form,
                material,
            },
            other => Node::Transform {
                transform: form,
                child: Box::new(other),
            },
        })
    }
}

/// The props of a scene file's table, or `None` where it has none of [`TABLES`].
pub fn read(root: &toml::Table) -> Result<Option<Scene>> {
    if TABLES.iter().all(|t| !root.contains_key(*t)) {
        return Ok(None);
    }
    let shipped = kinds::landscape();
    let materials = match root.get("prop_materials") {
        None => shipped.materials.clone(),
        Some(v) => table("prop_materials", v)?
            .iter()
            .map(|(name, m)| {
                let key = format!("prop_materials.{name}");
                let m = table(&key, m)?;
                only(&key, m, &["albedo", "variation"])?;
                Ok(Material {
                    name: name.clone(),
                    albedo: m
                        .get("albedo")
                        .map_or(Ok([0.5; 3]), |v| triple(&format!("{key}.albedo"), v))?,
                    variation: m
                        .get("variation")
                        .map_or(Ok(0.3), |v| number(&format!("{key}.variation"), v))?,
                })
            })
            .collect::<Result<Vec<_>>>()?,
    };
    let reader = Reader {
        materials: &materials,
    };
    let kinds = match root.get("prop_kinds") {
        None => shipped.kinds.clone(),
        Some(v) => table("prop_kinds", v)?
            .iter()
            .map(|(name, k)| {
                let key = format!("prop_kinds.{name}");
                let k = table(&key, k)?;
                only(&key, k, &["root", "weight", "scale", "on_rock"])?;
                let root = k
                    .get("root")
                    .ok_or_else(|| invalid(&format!("{key}.root"), "missing", "a node"))?;
                let scale = match k.get("scale") {
                    None => (1.0, 1.0),
                    Some(toml::Value::Array(a)) if a.len() == 2 => (
                        number(&format!("{key}.scale"), &a[0])?,
                        number(&format!("{key}.scale"), &a[1])?,
                    ),
                    Some(other) => {
                        let s = number(&format!("{key}.scale"), other)?;
                        (s, s)
                    }
                };
                Ok(Kind {
                    name: name.clone(),
                    root: reader.node(&format!("{key}.root"), root, 1)?,
                    weight: k
                        .get("weight")
                        .map_or(Ok(1.0), |v| number(&format!("{key}.weight"), v))?,
                    scale,
                    on_rock: match k.get("on_rock") {
                        None => true,
                        Some(toml::Value::Boolean(b)) => *b,
                        Some(other) => {
                            return Err(invalid(
                                &format!("{key}.on_rock"),
                                shown(other),
                                "true or false",
                            ))
                        }
                    },
                })
            })
            .collect::<Result<Vec<_>>>()?,
    };
    let placed = match root.get("prop_place") {
        None => Vec::new(),
        Some(toml::Value::Array(a)) => a
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let key = format!("prop_place[{i}]");
                let p = table(&key, p)?;
                only(&key, p, &["kind", "at", "turn", "scale"])?;
                let kind = match p.get("kind") {
                    Some(toml::Value::String(name)) => {
                        kinds.iter().position(|k| &k.name == name).ok_or_else(|| {
                            let names: Vec<&str> = kinds.iter().map(|k| k.name.as_str()).collect();
                            invalid(&format!("{key}.kind"), name, &names.join(", "))
                        })? as u32
                    }
                    other => {
                        return Err(invalid(
                            &format!("{key}.kind"),
                            other.map_or("missing".into(), shown),
                            "a kind's name",
                        ))
                    }
                };
                let at = match p.get("at") {
                    Some(toml::Value::Array(a)) if a.len() == 2 => [
                        number64(&format!("{key}.at"), &a[0])?,
                        number64(&format!("{key}.at"), &a[1])?,
                    ],
                    other => {
                        return Err(invalid(
                            &format!("{key}.at"),
                            other.map_or("missing".into(), shown),
                            "[x, z], world metres",
                        ))
                    }
                };
                Ok(Placed {
                    kind,
                    at,
                    turn: p
                        .get("turn")
                        .map_or(Ok(0.0), |v| number(&format!("{key}.turn"), v))?,
                    scale: p
                        .get("scale")
                        .map_or(Ok(1.0), |v| number(&format!("{key}.scale"), v))?,
                })
            })
            .collect::<Result<Vec<_>>>()?,
        Some(other) => return Err(invalid("prop_place", shown(other), "[[prop_place]] tables")),
    };
    Ok(Some(Scene {
        materials,
        kinds,
        placed,
    }))
}
