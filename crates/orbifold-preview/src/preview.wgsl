// The non-Euclidean projection of ARCHITECTURE.md §9, in closed form. `projection.rs` is its exact
// twin on the CPU (tests hold the two to the same pixels).

const TAU: f32 = 6.283185307179586;

struct Globals {
    // Camera basis in the eye's frame (model +x, model +y, up); w: kappa, eye height, mode.
    right: vec4<f32>,
    up: vec4<f32>,
    forward: vec4<f32>,
    // 1/(tan(fov/2)·aspect), 1/tan(fov/2), near, far.
    lens: vec4<f32>,
    // xy: the eye's flat position (2x, 2y) for the straight projection; z: ambient light; w: unused.
    eye: vec4<f32>,
};

struct Part {
    color: vec4<f32>,
    second: vec4<f32>,
    transform: mat3x4<f32>,
    code: i32,
    mirror: u32,
    pad: vec2<u32>,
    frame: vec4<f32>,
};

@group(0) @binding(0) var<uniform> globals: Globals;
@group(0) @binding(1) var<uniform> parts: array<Part, MAX_PARTS>;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) height: f32,
    @location(2) pattern: vec3<f32>,
    @location(3) part: u32,
};

struct InstanceIn {
    @location(4) m0: vec4<f32>,
    @location(5) m1: vec4<f32>,
    @location(6) m2: vec4<f32>,
    // rgb: the copy's brightness; a: which image (S²×R: 0 the short way, 1 the long way, ...).
    @location(7) tint: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) tangent: vec3<f32>,
    @location(1) pattern: vec3<f32>,
    @location(2) tint: vec3<f32>,
    @location(3) @interpolate(flat) part: u32,
    @location(4) @interpolate(flat) depth: f32,
    @location(5) @interpolate(flat) vertex: u32,
};

// The logarithm map at the eye of a point q (ambient, in the eye's frame), for one image.
fn eye_log(q: vec3<f32>, kappa: f32, image: f32) -> vec2<f32> {
    let r = length(q.xy);
    var d: f32;
    if kappa > 0.5 {
        d = atan2(r, q.z);
    } else if kappa < -0.5 {
        d = asinh(r);
    } else {
        d = r / q.z;
    }
    var direction = vec2<f32>(1.0, 0.0);
    if r > 0.0 {
        direction = q.xy / r;
    }
    let turns = floor(image * 0.5);
    if image - 2.0 * turns > 0.5 {
        d = TAU * (turns + 1.0) - d;
        direction = -direction;
    } else {
        d = d + TAU * turns;
    }
    return d * direction;
}

@vertex
fn vs_main(v: VertexIn, inst: InstanceIn, @builtin(vertex_index) index: u32) -> VertexOut {
    let part = parts[v.part];
    let object = mat3x3<f32>(part.transform[0].xyz, part.transform[1].xyz, part.transform[2].xyz);
    let copy = mat3x3<f32>(inst.m0.xyz, inst.m1.xyz, inst.m2.xyz);
    let q = copy * (object * v.position);
    let dh = v.height + part.transform[0].w - globals.up.w;
    var t: vec3<f32>;
    if globals.forward.w > 0.5 {
        // Straight: the model picture as flat space.
        let z = q.xy / (1.0 + q.z);
        t = vec3<f32>(2.0 * z - globals.eye.xy, dh);
    } else {
        t = vec3<f32>(eye_log(q, globals.right.w, inst.tint.w), dh);
    }
    let c = vec3<f32>(dot(t, globals.right.xyz), dot(t, globals.up.xyz), dot(t, globals.forward.xyz));
    let near = globals.lens.z;
    let far = globals.lens.w;
    // Depth: the geodesic length, 0 at the near plane; the rasteriser divides by w = c.z.
    let depth = (c.z - near) * length(t) / far;
    var out: VertexOut;
    out.clip = vec4<f32>(c.x * globals.lens.x, c.y * globals.lens.y, depth, c.z);
    out.tangent = t;
    out.pattern = v.pattern;
    out.tint = inst.tint.rgb;
    out.part = v.part;
    out.depth = inst.m0.w;
    out.vertex = index;
    return out;
}


fn albedo(part: Part, pattern: vec3<f32>) -> vec3<f32> {
    let size = part.color.w;
    if size > 0.0 {
        let cell = floor(pattern / size);
        let parity = i32(cell.x + cell.y + cell.z) & 1;
        if parity == 1 {
            return part.second.rgb;
        }
    }
    return part.color.rgb;
}

// Flat shading from a headlight at the eye: the face normal in the eye's tangent space.
fn shade(tangent: vec3<f32>) -> f32 {
    let n = cross(dpdx(tangent), dpdy(tangent));
    let facing = abs(dot(normalize(n), normalize(tangent)));
    if facing != facing {
        return 1.0;
    }
    return globals.eye.z + (1.0 - globals.eye.z) * facing;
}

@fragment
fn fs_opaque(v: VertexOut) -> @location(0) vec4<f32> {
    let part = parts[v.part];
    return vec4<f32>(albedo(part, v.pattern) * shade(v.tangent) * v.tint, 1.0);
}

// The surface code of what the pixel shows (the tracer's surface-id AOV).
@fragment
fn fs_id(v: VertexOut) -> @location(0) i32 {
    return parts[v.part].code;
}

// Mirrors: a frame along their edges; the room's own mirrors also a faint glass. Copies behind
// a mirror stay visible.
@fragment
fn fs_mirror(v: VertexOut) -> @location(0) vec4<f32> {
    let part = parts[v.part];
    let f = part.frame;
    let edge = min(
        min(v.pattern.x - f.x, f.y - v.pattern.x) / max(fwidth(v.pattern.x), 1e-6),
        min(v.pattern.y - f.z, f.w - v.pattern.y) / max(fwidth(v.pattern.y), 1e-6),
    );
    // About 1.5 pixels wide, wider (up to 0.012 units) where the mirror is near.
    let width = max(1.5, 0.012 / max(fwidth(v.pattern.y), 1e-6));
    // Frames of far copies fade, so that the copies' contents are not hidden behind a
    // thicket of frames at the horizon.
    let frame = (1.0 - smoothstep(width - 0.75, width + 0.75, edge)) * pow(0.8, v.depth);
    var alpha = frame;
    if v.depth < 0.5 {
        alpha = max(alpha, part.second.a);
    }
    if alpha <= 0.0 {
        discard;
    }
    return vec4<f32>(part.color.rgb * 0.55 * v.tint, alpha);
}

// Vertices drawn as points, each writing its own index: where every vertex lands.
@fragment
fn fs_point(v: VertexOut) -> @location(0) i32 {
    return i32(v.vertex);
}
