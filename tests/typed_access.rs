//! Access rights in the generated addresses, checked by the compiler (trybuild): a master's
//! typed write of a read-only or constant entry and its typed read of a write-only one do not
//! compile, through the blocking `Master`, the `AsyncMaster` and the sans-IO `SdoClient`, each
//! with the exact error in `tests/typed_access/*.stderr`; what stays allowed compiles and runs.
//!
//! The `.stderr` files are rustc's output on this repository's pinned toolchain; after a
//! deliberate change, `TRYBUILD=overwrite cargo test --test typed_access` rewrites them.

#[test]
fn typed_access_is_checked_at_compile_time() {
    let cases = trybuild::TestCases::new();
    cases.pass("tests/typed_access/allowed.rs");
    cases.compile_fail("tests/typed_access/blocking_master.rs");
    cases.compile_fail("tests/typed_access/async_master.rs");
    cases.compile_fail("tests/typed_access/sdo_client.rs");
}
