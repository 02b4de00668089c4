// The non-Euclidean projection of ARCHITECTURE.md §9, in closed form. `projection.rs` is its exact
// twin on the CPU (tests hold the two to the same pixels).

const TAU: f32 = 6.283185307179586;
const PI: f32 = 3.141592653589793;

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
    // 0 plain, 1 checkerboard, 2 image (layer), 3 marble (mesh.rs, `PartStyle::pattern`).
    pattern: u32,
    layer: u32,
    frame: vec4<f32>,
};

@group(0) @binding(0) var<uniform> globals: Globals;
@group(0) @binding(1) var<uniform> parts: array<Part, MAX_PARTS>;
// The scene's images, one a layer (textures.rs); nearest texels, repeating.
@group(0) @binding(2) var images: texture_2d_array<f32>;
@group(0) @binding(3) var image_sampler: sampler;

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


// The pattern's colour at texture coordinates `pattern` (docs/scene-format.md, "Where a
// pattern lies"), as the renderer's textures give it.
//
// `uv` is an image's coordinates, and `du`, `dv` their derivatives across the screen, taken by
// the caller where control flow is uniform (as derivatives must be).
fn albedo(part: Part, pattern: vec3<f32>, uv: vec2<f32>, du: vec2<f32>, dv: vec2<f32>) -> vec3<f32> {
    let size = part.color.w;
    switch part.pattern {
        case 1u: {
            if size > 0.0 {
                let cell = floor(pattern / size);
                let parity = i32(cell.x + cell.y + cell.z) & 1;
                if parity == 1 {
                    return part.second.rgb;
                }
            }
        }
        case 2u: {
            return textureSampleGrad(images, image_sampler, uv, part.layer, du, dv).rgb;
        }
        case 3u: {
            return marble(pattern / size, part.color.rgb, part.second.rgb);
        }
        default: {}
    }
    return part.color.rgb;
}

// Marble as the renderer makes it (orbifold-render, textures/marble.rs; Perlin 1985): veins of
// `vein` in a `ground`, the level sets of a sine of x perturbed by turbulence. The lattice's
// gradients are chosen by the same SplitMix64 hash, in 64-bit arithmetic on pairs of u32 (low,
// high), so that the veins lie where the tracer puts them.
fn marble(q: vec3<f32>, ground: vec3<f32>, vein: vec3<f32>) -> vec3<f32> {
    var turbulence = 0.0;
    var frequency = 1.0;
    for (var octave = 0; octave < 6; octave++) {
        turbulence += abs(gradient_noise(q * frequency)) / frequency;
        frequency *= 2.0;
    }
    let s = sin(PI * (q.x + 0.5 * q.y + 3.0 * turbulence));
    let t = pow(clamp(1.0 - abs(s), 0.0, 1.0), 4.0);
    return clamp(ground + (vein - ground) * t, min(ground, vein), max(ground, vein));
}

// Perlin's improved gradient noise with a quintic fade.
fn gradient_noise(p: vec3<f32>) -> f32 {
    let cell = floor(p);
    let f = p - cell;
    let i = vec3<i32>(cell);
    let u = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
    let x00 = mix(corner(i, f, vec3<i32>(0, 0, 0)), corner(i, f, vec3<i32>(1, 0, 0)), u.x);
    let x10 = mix(corner(i, f, vec3<i32>(0, 1, 0)), corner(i, f, vec3<i32>(1, 1, 0)), u.x);
    let x01 = mix(corner(i, f, vec3<i32>(0, 0, 1)), corner(i, f, vec3<i32>(1, 0, 1)), u.x);
    let x11 = mix(corner(i, f, vec3<i32>(0, 1, 1)), corner(i, f, vec3<i32>(1, 1, 1)), u.x);
    return mix(mix(x00, x10, u.y), mix(x01, x11, u.y), u.z);
}

fn corner(i: vec3<i32>, f: vec3<f32>, d: vec3<i32>) -> f32 {
    let c = i + d;
    return dot(lattice_gradient(c.x, c.y, c.z), f - vec3<f32>(d));
}

// One of Perlin's 12 cube-edge gradients, chosen by SplitMix64(SplitMix64(SplitMix64(x) ^ y) ^ z)
// mod 12, each integer sign-extended to 64 bits.
fn lattice_gradient(x: i32, y: i32, z: i32) -> vec3<f32> {
    let h = splitmix64(xor64(splitmix64(xor64(splitmix64(widen(x)), widen(y))), widen(z)));
    // (high·2³² + low) mod 12, with 2³² ≡ 4 (mod 12).
    let k = ((h.y % 12u) * 4u + h.x % 12u) % 12u;
    let a = select(1.0, -1.0, (k & 1u) != 0u);
    let b = select(1.0, -1.0, (k & 2u) != 0u);
    if k < 4u {
        return vec3<f32>(a, b, 0.0);
    }
    if k < 8u {
        return vec3<f32>(a, 0.0, b);
    }
    return vec3<f32>(0.0, a, b);
}

fn widen(v: i32) -> vec2<u32> {
    return vec2<u32>(bitcast<u32>(v), select(0u, 0xffffffffu, v < 0));
}

fn xor64(a: vec2<u32>, b: vec2<u32>) -> vec2<u32> {
    return a ^ b;
}

// a >> n for 0 < n < 32.
fn shr64(a: vec2<u32>, n: u32) -> vec2<u32> {
    return vec2<u32>((a.x >> n) | (a.y << (32u - n)), a.y >> n);
}

fn add64(a: vec2<u32>, b: vec2<u32>) -> vec2<u32> {
    let low = a.x + b.x;
    return vec2<u32>(low, a.y + b.y + select(0u, 1u, low < a.x));
}

// The full 64-bit product of two u32, from their 16-bit halves.
fn wide_product(a: u32, b: u32) -> vec2<u32> {
    let a0 = a & 0xffffu;
    let a1 = a >> 16u;
    let b0 = b & 0xffffu;
    let b1 = b >> 16u;
    let p00 = a0 * b0;
    let p01 = a0 * b1;
    let p10 = a1 * b0;
    let middle = (p00 >> 16u) + (p01 & 0xffffu) + (p10 & 0xffffu);
    let low = (p00 & 0xffffu) | (middle << 16u);
    let high = a1 * b1 + (p01 >> 16u) + (p10 >> 16u) + (middle >> 16u);
    return vec2<u32>(low, high);
}

// a·b mod 2⁶⁴.
fn mul64(a: vec2<u32>, b: vec2<u32>) -> vec2<u32> {
    let low = wide_product(a.x, b.x);
    return vec2<u32>(low.x, low.y + a.x * b.y + a.y * b.x);
}

// The SplitMix64 finaliser (Steele, Lea & Flood 2014).
fn splitmix64(x: vec2<u32>) -> vec2<u32> {
    var z = add64(x, vec2<u32>(0x7F4A7C15u, 0x9E3779B9u));
    z = mul64(z ^ shr64(z, 30u), vec2<u32>(0x1CE4E5B9u, 0xBF58476Du));
    z = mul64(z ^ shr64(z, 27u), vec2<u32>(0x133111EBu, 0x94D049BBu));
    return z ^ shr64(z, 31u);
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
    // An image's coordinates: v runs up the image from its bottom row, the texture's rows run
    // down from its top.
    let uv = vec2<f32>(v.pattern.x, -v.pattern.y) / part.color.w + vec2<f32>(0.0, 1.0);
    let colour = albedo(part, v.pattern, uv, dpdx(uv), dpdy(uv));
    return vec4<f32>(colour * shade(v.tangent) * v.tint, 1.0);
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
