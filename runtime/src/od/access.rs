//! Access rights in the type of an address: zero-sized markers for `Entry`'s third parameter,
//! so that a master's typed SDO access the entry refuses does not compile.
//!
//! Generated code gives each address the marker of its entry's AccessType: `rw`, `rwr` and
//! `rww` leave the default [`ReadWrite`], `ro` is [`ReadOnly`], `const` is [`Const`] and `wo` is
//! [`WriteOnly`]. A master's typed `read` asks for [`Readable`] and its typed `write` for
//! [`Writable`], so `master.write(3, cp301::od::STATUSWORD, 0)` is a compile error where it
//! would otherwise be abort 0601 0002h at run time. The device application is not an SDO
//! client: its `Od::get` and `Od::set` take any marker (it keeps its own read-only statusword
//! current). An address built by hand ([`Entry::new`](crate::Entry::new)) is of unknown access
//! and so [`ReadWrite`]: the node's abort answers an access it refuses; `read_only()`,
//! `write_only()` and `constant()` narrow it. To try a refused access on purpose (a test of the
//! node's abort), build the address by hand from the generated one's `index` and `sub`.
//!
//! Why markers and not a field checked at run time: the error is the compiler's, at the line of
//! the mistake, and the address keeps its size (the markers are uninhabited types, present only
//! in the type). Why a third parameter with a default: code that names `Entry<u16>` or
//! `Entry<u16, Od>` means a read-write address and keeps compiling. `Readable` and `Writable` are
//! implemented exactly for the markers a CiA 301 SDO client may read or write.

/// The marker of an entry that may be read and written (`rw`, `rwr`, `rww`), and of an address
/// whose access is not known.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ReadWrite {}

/// The marker of a read-only entry (`ro`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ReadOnly {}

/// The marker of a write-only entry (`wo`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum WriteOnly {}

/// The marker of a constant entry (`const`): read-only, and its value never changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Const {}

/// The access markers an SDO client may read: all but [`WriteOnly`].
#[diagnostic::on_unimplemented(
    message = "a master cannot read a write-only entry",
    label = "the address of a write-only entry",
    note = "the node would answer SDO abort 0601 0001h (attempt to read a write-only object)"
)]
pub trait Readable {}
impl Readable for ReadWrite {}
impl Readable for ReadOnly {}
impl Readable for Const {}

/// The access markers an SDO client may write: [`ReadWrite`] and [`WriteOnly`].
#[diagnostic::on_unimplemented(
    message = "a master cannot write a read-only or constant entry",
    label = "the address of a read-only or constant entry",
    note = "the node would answer SDO abort 0601 0002h (attempt to write a read-only object)"
)]
pub trait Writable {}
impl Writable for ReadWrite {}
impl Writable for WriteOnly {}
