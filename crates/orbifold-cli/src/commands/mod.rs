//! One module per subcommand.

pub mod enumerate;
pub mod info;
pub mod layout;
