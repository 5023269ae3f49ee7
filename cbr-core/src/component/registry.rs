//! The registry of users' kinds of component, by name, through which a stored space that
//! names a custom kind (`Custom(kind: "log-grid", definition: ...)`) is read back.
//!
//! Spaces are read deep inside configs, case-base files and databases, where no context
//! can be passed down; so the registry is the process's, filled by the user's program at
//! start-up ([`register_component_kind`]) before it reads any space.

use super::custom::{ComponentKind, CustomComponent, KindError};
use std::any::TypeId;
use std::collections::BTreeMap;
use std::sync::{PoisonError, RwLock};

type Build = fn(&serde_json::Value) -> Result<CustomComponent, RegistryError>;

struct Registered {
    type_id: TypeId,
    type_name: &'static str,
    build: Build,
}

static KINDS: RwLock<BTreeMap<&'static str, Registered>> = RwLock::new(BTreeMap::new());

/// Why a kind cannot be registered, or a stored custom component cannot be read.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RegistryError {
    /// Another type is registered under the same kind name.
    #[error(
        "component kind `{kind}` is already registered by `{registered}`; `{refused}` needs another name"
    )]
    KindTaken {
        /// The kind name.
        kind: &'static str,
        /// The type registered under it.
        registered: &'static str,
        /// The type refused.
        refused: &'static str,
    },
    /// A stored component names a kind nobody registered.
    #[error(
        "unknown component kind `{kind}` (registered: {registered}); the program must register it with `register_component_kind` before reading the space"
    )]
    UnknownKind {
        /// The kind name read.
        kind: String,
        /// The registered kind names, or `none`.
        registered: String,
    },
    /// A definition the kind does not accept.
    #[error("component kind `{kind}`: {message}")]
    BadDefinition {
        /// The kind name.
        kind: &'static str,
        /// Why the kind refused it.
        message: String,
    },
    /// A definition the kind accepts that makes an unusable component.
    #[error(transparent)]
    Invalid(#[from] KindError),
}

/// Registers `K` under [`ComponentKind::KIND`], so spaces using it can be read back.
/// Registering the same type again does nothing; another type under a taken name is
/// refused.
pub fn register_component_kind<K: ComponentKind>() -> Result<(), RegistryError> {
    let mut kinds = KINDS.write().unwrap_or_else(PoisonError::into_inner);
    let refused = std::any::type_name::<K>();
    match kinds.get(K::KIND) {
        Some(known) if known.type_id == TypeId::of::<K>() => Ok(()),
        Some(known) => Err(RegistryError::KindTaken {
            kind: K::KIND,
            registered: known.type_name,
            refused,
        }),
        None => {
            kinds.insert(
                K::KIND,
                Registered {
                    type_id: TypeId::of::<K>(),
                    type_name: refused,
                    build: build::<K>,
                },
            );
            Ok(())
        }
    }
}

/// The names of the registered kinds, in alphabetical order.
pub fn registered_component_kinds() -> Vec<&'static str> {
    let kinds = KINDS.read().unwrap_or_else(PoisonError::into_inner);
    kinds.keys().copied().collect()
}

/// The custom component of registered kind `kind` read from `definition`.
pub(super) fn read(
    kind: &str,
    definition: &serde_json::Value,
) -> Result<CustomComponent, RegistryError> {
    let build = {
        let kinds = KINDS.read().unwrap_or_else(PoisonError::into_inner);
        match kinds.get(kind) {
            Some(registered) => registered.build,
            None => {
                let names: Vec<&str> = kinds.keys().copied().collect();
                return Err(RegistryError::UnknownKind {
                    kind: kind.to_owned(),
                    registered: if names.is_empty() {
                        "none".to_owned()
                    } else {
                        names.join(", ")
                    },
                });
            }
        }
    };
    build(definition)
}

fn build<K: ComponentKind>(
    definition: &serde_json::Value,
) -> Result<CustomComponent, RegistryError> {
    let component = K::deserialize(definition).map_err(|e| RegistryError::BadDefinition {
        kind: K::KIND,
        message: e.to_string(),
    })?;
    Ok(CustomComponent::new(component)?)
}
