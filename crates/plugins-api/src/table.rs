//! The part of a plugin table that both kinds share: the fields with which
//! [`FrictionPluginV1`](crate::abi::FrictionPluginV1) and
//! [`MaterialPluginV1`](crate::material::abi::MaterialPluginV1) begin
//! (version, name, summary, parameter schema) and the functions every table
//! has (`create`, `destroy`, `last_error`), as one [`Header`].
//!
//! The `#[repr(C)]` tables stay spelled out field by field in their modules
//! (they are the ABI); this module is the one place that copies the shared
//! fields into a table ([`with_header!`], plugin side) and out of one
//! ([`HasHeader::header`], host side), so the code of either side is written
//! once for both kinds.

use std::ffi::c_char;

use crate::abi::{AbiParamSpec, CreateFn, DestroyFn, FrictionPluginV1, LastErrorFn};
use crate::material::abi::MaterialPluginV1;

/// The fields that every plugin table has, under the same names and with
/// the same meaning (see [`FrictionPluginV1`](crate::abi::FrictionPluginV1)).
#[derive(Clone, Copy, Debug)]
pub struct Header {
    /// [`crate::ABI_VERSION`] of the `plugins-api` the plugin was built against.
    pub abi_version: u32,
    /// Name as typed in scenes, NUL-terminated.
    pub name: *const c_char,
    /// One-line summary, NUL-terminated.
    pub summary: *const c_char,
    /// Parameter schema, `n_params` entries.
    pub params: *const AbiParamSpec,
    /// Number of entries of `params`.
    pub n_params: usize,
    /// See [`CreateFn`].
    pub create: Option<CreateFn>,
    /// See [`DestroyFn`].
    pub destroy: Option<DestroyFn>,
    /// See [`LastErrorFn`].
    pub last_error: Option<LastErrorFn>,
}

/// A plugin table as the host reads it: its kind and its [`Header`].
pub(crate) trait HasHeader: Copy + 'static {
    /// `friction` or `material`: the kind, for messages and the entry
    /// symbol `formsim_{KIND}_plugin_v1`.
    const KIND: &'static str;
    /// What the table's name names (`law`, `material`), for messages.
    const NOUN: &'static str;
    /// The shared fields of the table.
    fn header(&self) -> Header;
}

/// `$table { $field: $value, … }` with the shared fields taken from
/// `$header` (a [`Header`]): the kind gives only its own fields.
macro_rules! with_header {
    ($table:ident { $($field:ident: $value:expr),* $(,)? } $header:expr) => {{
        let header: $crate::table::Header = $header;
        $table {
            abi_version: header.abi_version,
            name: header.name,
            summary: header.summary,
            params: header.params,
            n_params: header.n_params,
            create: header.create,
            destroy: header.destroy,
            last_error: header.last_error,
            $($field: $value),*
        }
    }};
}
pub(crate) use with_header;

/// Implement [`HasHeader`] for a table type: `Table: "kind", "noun"`.
macro_rules! impl_has_header {
    ($($table:ty: $kind:literal, $noun:literal;)*) => {$(
        impl HasHeader for $table {
            const KIND: &'static str = $kind;
            const NOUN: &'static str = $noun;
            fn header(&self) -> Header {
                Header {
                    abi_version: self.abi_version,
                    name: self.name,
                    summary: self.summary,
                    params: self.params,
                    n_params: self.n_params,
                    create: self.create,
                    destroy: self.destroy,
                    last_error: self.last_error,
                }
            }
        }
    )*};
}

impl_has_header! {
    FrictionPluginV1: "friction", "law";
    MaterialPluginV1: "material", "material";
}
