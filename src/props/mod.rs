//! Props: things that stand on the terrain, each a signed distance function (SDF) built of
//! primitives, booleans, transforms and noise displacement, placed by a hash over world cells
//! and marched in compute.
//!
//! - **A kind** ([`Kind`]) is a tree of [`Node`]s: primitives ([`Shape`]), sharp and smooth
//!   booleans ([`Combine`]), transforms ([`Transform`]) and noise displacement, with a material
//!   at each primitive. [`Kind::compile`] validates it at the boundary (one [`Error`] naming the
//!   key, the value and the limit) and flattens it into a [`Tape`]: at most [`MAX_TAPE`]
//!   instructions in postfix order, each primitive carrying its composed transform, which the
//!   GPU evaluates from a buffer with a stack (`wgsl/props.wgsl`) and the CPU twin
//!   ([`sdf`]) in f64. No recursion at evaluation: a tape is a loop.
//! - **Its bound**: the tape's distance never overestimates the distance to the surface by more
//!   than its Lipschitz constant allows ([`Tape::lipschitz`]): 1 for primitives, booleans and
//!   smooth booleans (the smooth minimum's gradient is a convex combination of its
//!   arguments'), times the largest over the smallest scale of a non-uniform scale, plus
//!   amplitude times frequency times [`NOISE_GRADIENT`] for each displacement. A march that
//!   divides each step by it never steps through a surface.
//! - **Its extent** ([`Tape::bounds`]): a box in the kind's frame that holds its surface, from
//!   the primitives' boxes (a smooth blend may bulge out by a quarter of its radius, a
//!   displacement by its amplitude). The placement checks it against the cell and the band.
//!
//! The shipped kinds are [`kinds`]; where they stand is [`place`].

pub mod kinds;
pub mod place;
pub mod query;
pub mod sdf;
#[cfg(test)]
mod tests;

use crate::error::{Error, Result};

/// The most instructions a kind's tape holds (primitives, each boolean of two, displacements).
pub const MAX_TAPE: usize = 64;
/// The deepest a kind's tree may nest.
pub const MAX_DEPTH: usize = 32;
/// The most kinds a scene holds.
pub const MAX_KINDS: usize = 256;
/// The most materials a scene holds.
pub const MAX_MATERIALS: usize = 16;
/// The evaluation stack's size (the deepest tree needs one more than its depth).
pub const STACK: usize = MAX_DEPTH + 1;

/// A bound on the gradient of [`sdf::value_noise`] (a value noise in [-1, 1] with a quintic
/// fade). Along each axis its slope is at most the fade's (15/8) times the largest difference of
/// two lattice values (2): 3.75. The gradient is linear in the lattice values, so its largest
/// norm is at lattice values of +-1: every one of their 256 patterns sampled at 41^3 places in a
/// cell finds 3.75 and no more (the axes' largest slopes never meet); 4.0 leaves a margin for
/// what sampling misses (a test samples the noise itself).
pub const NOISE_GRADIENT: f64 = 4.0;

/// A primitive, in its own frame (centred on the origin, y up), metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A sphere of `radius`.
    Sphere {
        /// Metres.
        radius: f32,
    },
    /// A box of half-extents `half`.
    Box {
        /// Half its size along x, y, z.
        half: [f32; 3],
    },
    /// A box of half-extents `half` with its edges rounded by `radius` (within the half-extents).
    RoundBox {
        /// Half its size along x, y, z.
        half: [f32; 3],
        /// The rounding, less than every half-extent.
        radius: f32,
    },
    /// A torus about the y axis: a ring of radius `major`, its tube of radius `minor`.
    Torus {
        /// The ring's radius.
        major: f32,
        /// The tube's radius.
        minor: f32,
    },
    /// A capped cylinder about the y axis.
    Cylinder {
        /// Its radius.
        radius: f32,
        /// Half its height.
        half_height: f32,
    },
    /// A capsule along the y axis: a segment from -half_height to half_height, swept by `radius`.
    Capsule {
        /// Its radius.
        radius: f32,
        /// Half its segment's length.
        half_height: f32,
    },
    /// The half-space below the plane through `offset * normal` with unit `normal` (pointing
    /// out). Unbounded: only inside an intersection or as what a subtraction removes.
    Plane {
        /// The outward normal (normalised when compiled).
        normal: [f32; 3],
        /// The plane's distance from the origin along the normal.
        offset: f32,
    },
}

impl Shape {
    /// The key scene files name it by.
    pub fn name(&self) -> &'static str {
        match self {
            Shape::Sphere { .. } => "sphere",
            Shape::Box { .. } => "box",
            Shape::RoundBox { .. } => "round_box",
            Shape::Torus { .. } => "torus",
            Shape::Cylinder { .. } => "cylinder",
            Shape::Capsule { .. } => "capsule",
            Shape::Plane { .. } => "plane",
        }
    }
}

/// How a boolean joins its children.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Combine {
    /// Inside any child.
    Union,
    /// Inside every child.
    Intersection,
    /// Inside the first child and outside the rest.
    Subtraction,
}

/// A transform: scale, then rotate (about x, then y, then z, degrees), then translate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    /// Metres.
    pub translate: [f32; 3],
    /// Degrees about x, y, z, applied in that order.
    pub rotate: [f32; 3],
    /// Per axis; a uniform scale keeps the field a distance, a non-uniform one raises its
    /// Lipschitz constant to the largest over the smallest.
    pub scale: [f32; 3],
}

impl Default for Transform {
    fn default() -> Self {
        Self {
            translate: [0.0; 3],
            rotate: [0.0; 3],
            scale: [1.0; 3],
        }
    }
}

impl Transform {
    /// A translation.
    pub fn at(translate: [f32; 3]) -> Self {
        Self {
            translate,
            ..Self::default()
        }
    }

    /// The affine map from the parent's frame to this node's frame and back, in f64.
    fn matrix(&self) -> glam::DAffine3 {
        let [rx, ry, rz] = self.rotate.map(|d| f64::from(d).to_radians());
        let r = glam::DQuat::from_rotation_z(rz)
            * glam::DQuat::from_rotation_y(ry)
            * glam::DQuat::from_rotation_x(rx);
        glam::DAffine3::from_scale_rotation_translation(
            glam::DVec3::from(self.scale.map(f64::from)),
            r,
            glam::DVec3::from(self.translate.map(f64::from)),
        )
    }
}

/// A node of a kind's tree.
#[derive(Clone, Debug, PartialEq)]
pub enum Node {
    /// A primitive with its material (an index into the scene's materials).
    Shape {
        /// What it is.
        shape: Shape,
        /// Where it is in its parent's frame.
        transform: Transform,
        /// Index into [`Scene::materials`].
        material: u32,
    },
    /// A boolean of two or more children, folded from the left; `smooth` blends over that
    /// radius (metres, > 0), `None` joins sharply.
    Combine {
        /// Union, intersection or subtraction.
        op: Combine,
        /// The blend's radius, metres (`None`: sharp).
        smooth: Option<f32>,
        /// Two or more.
        children: Vec<Node>,
    },
    /// A child moved, turned and scaled.
    Transform {
        /// The transform.
        transform: Transform,
        /// What it moves.
        child: Box<Node>,
    },
    /// A child's surface pushed out and in by a value noise: `amplitude` metres at most,
    /// `frequency` cycles a metre (in the displacement's frame).
    Displace {
        /// Metres.
        amplitude: f32,
        /// Cycles a metre.
        frequency: f32,
        /// What it roughens.
        child: Box<Node>,
    },
}

/// A material: a linear albedo and a shininess.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The name scene files refer to it by.
    pub name: String,
    /// Linear albedo, 0 to 1 each.
    pub albedo: [f32; 3],
    /// How much each prop's own shade varies it, 0 to 1.
    pub variation: f32,
}

/// A kind of prop: its tree and how it is placed.
#[derive(Clone, Debug, PartialEq)]
pub struct Kind {
    /// Its name (the scene file's key).
    pub name: String,
    /// Its shape, in a frame whose origin sits on the ground (y up). Parts below y = 0 are
    /// buried.
    pub root: Node,
    /// How often it is chosen where a prop stands, relative to the other kinds.
    pub weight: f32,
    /// The scale it is drawn at varies from `scale.0` to `scale.1` times its own.
    pub scale: (f32, f32),
    /// Whether it may stand on rock (steep ground); else only on gentle ground.
    pub on_rock: bool,
}

/// One instruction of a tape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instruction {
    /// What it does.
    pub op: Op,
    /// For a primitive: the map from the kind's frame to the primitive's own (rows of a 3x4
    /// matrix; for a displacement, to its noise's frame).
    pub to_local: [[f64; 4]; 3],
    /// For a primitive or a displacement: what its own distances are multiplied by to be
    /// distances in the kind's frame (the smallest scale on the way down).
    pub scale: f64,
    /// For a primitive: its material.
    pub material: u32,
}

/// What an instruction does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Op {
    /// Pushes a primitive's distance.
    Shape(Shape),
    /// Pops two distances, pushes their boolean (smooth over the radius where > 0).
    Combine(Combine, f32),
    /// Pops one distance, pushes it displaced by `amplitude` metres of noise at `frequency`.
    Displace {
        /// Metres, in the kind's frame.
        amplitude: f32,
        /// Cycles a metre of the displacement's own frame.
        frequency: f32,
    },
}

/// A kind's tree flattened for evaluation: postfix instructions and what was worked out about
/// them.
#[derive(Clone, Debug, PartialEq)]
pub struct Tape {
    /// The instructions, in the order they run.
    pub code: Vec<Instruction>,
    /// The field's Lipschitz constant (>= 1): a march divides each step by it.
    pub lipschitz: f64,
    /// The Lipschitz constant of the field without its displacements (>= 1, at most
    /// `lipschitz`): a step read from that field (less their amplitudes) is divided by it.
    pub lipschitz_undisplaced: f64,
    /// A box holding the surface in the kind's frame: min and max corners.
    pub bounds: [[f64; 3]; 2],
    /// The stack slots the tape needs.
    pub stack: usize,
}

impl Tape {
    /// The sum of its displacements' amplitudes (metres, the kind's frame): the field without
    /// them lies within this of the field with them (booleans, sharp or smooth, move their
    /// result by no more than they move their arguments).
    pub fn roughness(&self) -> f64 {
        self.code
            .iter()
            .map(|i| match i.op {
                Op::Displace { amplitude, .. } => f64::from(amplitude),
                _ => 0.0,
            })
            .sum()
    }

    /// The radius about the kind's vertical axis that holds its surface however it turns.
    pub fn radius(&self) -> f64 {
        let [lo, hi] = self.bounds;
        let x = lo[0].abs().max(hi[0].abs());
        let z = lo[2].abs().max(hi[2].abs());
        x.hypot(z)
    }
}

/// What props a world has: materials, kinds, and props put at given places. How they are
/// scattered is [`Props`], rows of the world's parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// At most [`MAX_MATERIALS`].
    pub materials: Vec<Material>,
    /// At most [`MAX_KINDS`].
    pub kinds: Vec<Kind>,
    /// Props at given places, besides the scattered ones (in water too).
    pub placed: Vec<place::Placed>,
}

pub use place::Props;

struct Compiler<'a> {
    key: &'a str,
    code: Vec<Instruction>,
    lipschitz: f64,
    undisplaced: f64,
    depth: usize,
    stack: usize,
    materials: usize,
}

fn positive(key: &str, v: f32) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(key, v, "a finite size > 0"))
    }
}

fn finite(key: &str, v: &[f32]) -> Result<()> {
    match v.iter().find(|x| !x.is_finite()) {
        Some(x) => Err(Error::invalid(key, x, "a finite number")),
        None => Ok(()),
    }
}

type Box3 = [[f64; 3]; 2];

const EVERYWHERE: Box3 = [[f64::NEG_INFINITY; 3], [f64::INFINITY; 3]];

fn grow(b: Box3, by: f64) -> Box3 {
    [b[0].map(|v| v - by), b[1].map(|v| v + by)]
}

/// The box holding the image of `b` under `m`.
fn transform_box(m: &glam::DAffine3, b: Box3) -> Box3 {
    if b.iter().flatten().any(|v| !v.is_finite()) {
        return EVERYWHERE;
    }
    let mut out = [[f64::INFINITY; 3], [f64::NEG_INFINITY; 3]];
    for i in 0..8 {
        let c = glam::DVec3::new(b[i & 1][0], b[(i >> 1) & 1][1], b[(i >> 2) & 1][2]);
        let p = m.transform_point3(c).to_array();
        for a in 0..3 {
            out[0][a] = out[0][a].min(p[a]);
            out[1][a] = out[1][a].max(p[a]);
        }
    }
    out
}

impl Compiler<'_> {
    /// Compiles `node` under the map `to_node` (the kind's frame to the node's parent's) whose
    /// distances scale by `scale` and whose Lipschitz factor so far is `stretch`; returns the
    /// box of its surface in the kind's frame.
    fn node(
        &mut self,
        node: &Node,
        path: &str,
        (to_parent, scale, stretch): (glam::DAffine3, f64, f64),
        (depth, height): (usize, usize),
    ) -> Result<Box3> {
        if depth > MAX_DEPTH {
            return Err(Error::invalid(
                format!("{}: {path}", self.key),
                format!("a tree {depth} deep"),
                format!("at most {MAX_DEPTH} deep"),
            ));
        }
        self.depth = self.depth.max(depth);
        if self.code.len() >= MAX_TAPE {
            return Err(Error::invalid(
                self.key,
                format!("more than {MAX_TAPE} instructions"),
                format!(
                    "at most {MAX_TAPE} (a primitive, each join of two children and each \
                     displacement count one)"
                ),
            ));
        }
        match node {
            Node::Shape {
                shape,
                transform,
                material,
            } => {
                let (to_local, s, st) =
                    self.transform(transform, path, (to_parent, scale, stretch))?;
                if *material as usize >= self.materials {
                    return Err(Error::invalid(
                        format!("{}: {path}.material", self.key),
                        material,
                        format!("one of the scene's {} materials", self.materials),
                    ));
                }
                let shape = self.shape(shape, path)?;
                self.lipschitz = self.lipschitz.max(st);
                self.undisplaced = self.undisplaced.max(st);
                self.stack = self.stack.max(height + 1);
                self.code.push(Instruction {
                    op: Op::Shape(shape),
                    to_local: rows(&to_local),
                    scale: s,
                    material: *material,
                });
                Ok(transform_box(&to_local.inverse(), shape_box(&shape)))
            }
            Node::Transform { transform, child } => {
                let inner = self.transform(transform, path, (to_parent, scale, stretch))?;
                self.node(child, &format!("{path}.child"), inner, (depth + 1, height))
            }
            Node::Combine {
                op,
                smooth,
                children,
            } => {
                if children.len() < 2 {
                    return Err(Error::invalid(
                        format!("{}: {path}.children", self.key),
                        children.len(),
                        "two or more",
                    ));
                }
                let radius = match *smooth {
                    None => 0.0,
                    Some(k) if k.is_finite() && k > 0.0 => f64::from(k) * scale,
                    Some(k) => {
                        return Err(Error::invalid(
                            format!("{}: {path}.smooth", self.key),
                            k,
                            "a finite radius > 0",
                        ))
                    }
                };
                let mut acc = EVERYWHERE;
                for (i, child) in children.iter().enumerate() {
                    let b = self.node(
                        child,
                        &format!("{path}.children[{i}]"),
                        (to_parent, scale, stretch),
                        (depth + 1, height + usize::from(i > 0)),
                    )?;
                    if i == 0 {
                        acc = b;
                        continue;
                    }
                    acc = match op {
                        Combine::Union => [
                            [0, 1, 2].map(|a| acc[0][a].min(b[0][a])),
                            [0, 1, 2].map(|a| acc[1][a].max(b[1][a])),
                        ],
                        Combine::Intersection => [
                            [0, 1, 2].map(|a| acc[0][a].max(b[0][a])),
                            [0, 1, 2].map(|a| acc[1][a].min(b[1][a])),
                        ],
                        Combine::Subtraction => acc,
                    };
                    // The smooth blend lowers the field by at most a quarter of its radius.
                    acc = grow(acc, radius / 4.0);
                    if self.code.len() >= MAX_TAPE {
                        return Err(Error::invalid(
                            self.key,
                            format!("more than {MAX_TAPE} instructions"),
                            format!("at most {MAX_TAPE}"),
                        ));
                    }
                    self.code.push(Instruction {
                        op: Op::Combine(*op, radius as f32),
                        to_local: rows(&glam::DAffine3::IDENTITY),
                        scale: 1.0,
                        material: 0,
                    });
                }
                Ok(acc)
            }
            Node::Displace {
                amplitude,
                frequency,
                child,
            } => {
                positive(&format!("{}: {path}.amplitude", self.key), *amplitude)?;
                positive(&format!("{}: {path}.frequency", self.key), *frequency)?;
                let b = self.node(
                    child,
                    &format!("{path}.child"),
                    (to_parent, scale, stretch),
                    (depth + 1, height),
                )?;
                let amplitude = f64::from(*amplitude) * scale;
                // The noise is read in the displacement's frame at `frequency` cycles a unit,
                // which a unit of the kind's frame spans at most 1 / scale of: its slope in the
                // kind's frame is at most amplitude * frequency / scale * NOISE_GRADIENT.
                let slope = amplitude * f64::from(*frequency) / scale * NOISE_GRADIENT;
                self.lipschitz += slope;
                self.code.push(Instruction {
                    op: Op::Displace {
                        amplitude: amplitude as f32,
                        frequency: *frequency,
                    },
                    to_local: rows(&to_parent),
                    scale,
                    material: 0,
                });
                Ok(grow(b, amplitude))
            }
        }
    }

    /// The map into a transform's frame and its scale and stretch, validated.
    fn transform(
        &self,
        t: &Transform,
        path: &str,
        (to_parent, scale, stretch): (glam::DAffine3, f64, f64),
    ) -> Result<(glam::DAffine3, f64, f64)> {
        finite(&format!("{}: {path}.translate", self.key), &t.translate)?;
        finite(&format!("{}: {path}.rotate", self.key), &t.rotate)?;
        for s in t.scale {
            if !s.is_finite() || s <= 0.0 {
                return Err(Error::invalid(
                    format!("{}: {path}.scale", self.key),
                    s,
                    "a finite scale > 0",
                ));
            }
        }
        let lo = f64::from(t.scale.iter().copied().fold(f32::INFINITY, f32::min));
        let hi = f64::from(t.scale.iter().copied().fold(0.0, f32::max));
        let to_local = t.matrix().inverse() * to_parent;
        Ok((to_local, scale * lo, stretch * hi / lo))
    }

    fn shape(&self, shape: &Shape, path: &str) -> Result<Shape> {
        let key = |k: &str| format!("{}: {path}.{}.{k}", self.key, shape.name());
        match *shape {
            Shape::Sphere { radius } => positive(&key("radius"), radius)?,
            Shape::Box { half } => {
                for h in half {
                    positive(&key("size"), h)?;
                }
            }
            Shape::RoundBox { half, radius } => {
                for h in half {
                    positive(&key("size"), h)?;
                }
                positive(&key("radius"), radius)?;
                let least = half.iter().copied().fold(f32::INFINITY, f32::min);
                if radius >= least {
                    return Err(Error::invalid(
                        key("radius"),
                        radius,
                        format!("less than the box's least half-size, {least}"),
                    ));
                }
            }
            Shape::Torus { major, minor } => {
                positive(&key("major"), major)?;
                positive(&key("minor"), minor)?;
            }
            Shape::Cylinder {
                radius,
                half_height,
            }
            | Shape::Capsule {
                radius,
                half_height,
            } => {
                positive(&key("radius"), radius)?;
                positive(&key("half_height"), half_height)?;
            }
            Shape::Plane { normal, offset } => {
                finite(&key("normal"), &normal)?;
                finite(&key("offset"), &[offset])?;
                let n = glam::Vec3::from(normal);
                if n.length() < 1e-6 {
                    return Err(Error::invalid(
                        key("normal"),
                        "[0, 0, 0]",
                        "a non-zero vector",
                    ));
                }
                return Ok(Shape::Plane {
                    normal: n.normalize().to_array(),
                    offset,
                });
            }
        }
        Ok(*shape)
    }
}

fn rows(m: &glam::DAffine3) -> [[f64; 4]; 3] {
    let c = m.matrix3;
    let t = m.translation;
    [
        [c.x_axis.x, c.y_axis.x, c.z_axis.x, t.x],
        [c.x_axis.y, c.y_axis.y, c.z_axis.y, t.y],
        [c.x_axis.z, c.y_axis.z, c.z_axis.z, t.z],
    ]
}

/// The box holding a primitive in its own frame.
fn shape_box(shape: &Shape) -> Box3 {
    let sym = |h: [f64; 3]| [h.map(|v| -v), h];
    match *shape {
        Shape::Sphere { radius } => sym([f64::from(radius); 3]),
        Shape::Box { half } | Shape::RoundBox { half, .. } => sym(half.map(f64::from)),
        Shape::Torus { major, minor } => {
            let r = f64::from(major + minor);
            sym([r, f64::from(minor), r])
        }
        Shape::Cylinder {
            radius,
            half_height,
        } => sym([f64::from(radius), f64::from(half_height), f64::from(radius)]),
        Shape::Capsule {
            radius,
            half_height,
        } => sym([
            f64::from(radius),
            f64::from(half_height + radius),
            f64::from(radius),
        ]),
        Shape::Plane { .. } => EVERYWHERE,
    }
}

impl Kind {
    /// Validates the kind (see the module's docs) for a scene of `materials` materials and
    /// flattens it; errors name the key (`props.<kind>: <path>`), the value and the limit.
    pub fn compile(&self, materials: usize) -> Result<Tape> {
        let key = format!("prop_kinds.{}", self.name);
        let mut c = Compiler {
            key: &key,
            code: Vec::new(),
            lipschitz: 1.0,
            undisplaced: 1.0,
            depth: 0,
            stack: 0,
            materials,
        };
        let bounds = c.node(
            &self.root,
            "root",
            (glam::DAffine3::IDENTITY, 1.0, 1.0),
            (1, 0),
        )?;
        if bounds.iter().flatten().any(|v| !v.is_finite()) {
            return Err(Error::invalid(
                format!("{key}: root"),
                "an unbounded shape (a plane not inside an intersection)",
                "a bounded prop",
            ));
        }
        let (lo, hi) = self.scale;
        if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi >= lo) {
            return Err(Error::invalid(
                format!("{key}.scale"),
                format!("[{lo}, {hi}]"),
                "0 < min <= max, finite",
            ));
        }
        if !(self.weight.is_finite() && self.weight >= 0.0) {
            return Err(Error::invalid(
                format!("{key}.weight"),
                self.weight,
                "a finite weight >= 0",
            ));
        }
        Ok(Tape {
            code: c.code,
            lipschitz: c.lipschitz,
            lipschitz_undisplaced: c.undisplaced,
            bounds,
            stack: c.stack,
        })
    }
}

impl Default for Scene {
    /// The shipped landscape's ([`kinds::landscape`]).
    fn default() -> Self {
        kinds::landscape()
    }
}

impl Scene {
    /// Validates every kind and the props put at given places against how `props` scatters
    /// them, and compiles the kinds' tapes, in order.
    pub fn compile(&self, props: &Props) -> Result<Vec<Tape>> {
        if self.kinds.len() > MAX_KINDS {
            return Err(Error::invalid(
                "prop_kinds",
                format!("{} kinds", self.kinds.len()),
                format!("at most {MAX_KINDS}"),
            ));
        }
        if self.materials.is_empty() || self.materials.len() > MAX_MATERIALS {
            return Err(Error::invalid(
                "prop_materials",
                format!("{} materials", self.materials.len()),
                format!("1 to {MAX_MATERIALS}"),
            ));
        }
        for m in &self.materials {
            let key = format!("prop_materials.{}", m.name);
            if let Some(v) = m
                .albedo
                .iter()
                .chain([&m.variation])
                .find(|v| !(0.0..=1.0).contains(*v))
            {
                return Err(Error::invalid(key, v, "0 to 1"));
            }
        }
        props.validate()?;
        Props::validate_placed(&self.placed)?;
        let tapes = self
            .kinds
            .iter()
            .map(|k| k.compile(self.materials.len()))
            .collect::<Result<Vec<_>>>()?;
        for (i, p) in self.placed.iter().enumerate() {
            if p.kind as usize >= self.kinds.len() {
                return Err(Error::invalid(
                    format!("prop_place[{i}].kind"),
                    p.kind,
                    format!("one of the scene's {} kinds", self.kinds.len()),
                ));
            }
        }
        for (i, (kind, tape)) in self.kinds.iter().zip(&tapes).enumerate() {
            props.check_fits(kind, tape, (i as u32, &self.placed))?;
        }
        Ok(tapes)
    }
}
