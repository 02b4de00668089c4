//! Materials: how a surface scatters light ([`bsdf`]).

pub mod bsdf;
