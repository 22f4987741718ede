//! The dictionary's items that are the same in every module (`Od`, `impl Od`, the
//! `ObjectDictionary` implementation), written as the text `prettyplease` prints for them:
//! parsing and printing them again was a quarter of formatting a module. A test checks that
//! printing them again changes nothing.

/// `Od` and `impl Od`.
pub fn od_struct() -> String {
    let mut out = String::with_capacity(OD_HEAD.len() + OD_TAIL.len());
    out.push_str(OD_HEAD);
    out.push_str(OD_TAIL);
    out
}

/// `impl ObjectDictionary for Od`: every access goes through `LAYOUT`, by position in
/// `ENTRIES`; `read` and `write` find the position with one search of `DESCRIPTORS`.
pub const OD_IMPL: &str = r##"    impl ::edsgen_runtime::ObjectDictionary for Od {
        fn entry_count(&self) -> usize {
            LAYOUT.entry_count()
        }
        fn entry(&self, position: usize) -> Option<::edsgen_runtime::EntryDescriptor> {
            LAYOUT.entry(position)
        }
        #[inline]
        fn kind(&self, position: usize) -> Option<::edsgen_runtime::EntryKind> {
            LAYOUT.kind(position)
        }
        fn locate(
            &self,
            index: u16,
            sub: u8,
        ) -> Result<usize, ::edsgen_runtime::SdoAbort> {
            LAYOUT.locate(index, sub)
        }
        #[inline]
        fn services(&self) -> ::edsgen_runtime::Services {
            SERVICES
        }
        fn capacity(&self, position: usize) -> Option<usize> {
            LAYOUT.capacity(position)
        }
        fn value_len(
            &self,
            index: u16,
            sub: u8,
        ) -> Result<usize, ::edsgen_runtime::SdoAbort> {
            LAYOUT.value_len(&self.values, LAYOUT.locate(index, sub)?)
        }
        fn value_len_at(
            &self,
            position: usize,
        ) -> Result<usize, ::edsgen_runtime::SdoAbort> {
            LAYOUT.value_len(&self.values, position)
        }
        fn read(
            &self,
            index: u16,
            sub: u8,
            offset: usize,
            buf: &mut [u8],
        ) -> Result<usize, ::edsgen_runtime::SdoAbort> {
            self.read_at(LAYOUT.locate(index, sub)?, offset, buf)
        }
        fn write(
            &mut self,
            index: u16,
            sub: u8,
            data: &[u8],
        ) -> Result<(), ::edsgen_runtime::SdoAbort> {
            self.write_at(LAYOUT.locate(index, sub)?, data)
        }
        fn read_at(
            &self,
            position: usize,
            offset: usize,
            buf: &mut [u8],
        ) -> Result<usize, ::edsgen_runtime::SdoAbort> {
            LAYOUT.read(&self.values, position, offset, buf)
        }
        fn write_at(
            &mut self,
            position: usize,
            data: &[u8],
        ) -> Result<(), ::edsgen_runtime::SdoAbort> {
            LAYOUT.write(&mut self.values, position, data)
        }
        fn begin_write(
            &mut self,
            position: usize,
        ) -> Result<(), ::edsgen_runtime::SdoAbort> {
            self.stage.begin(position)
        }
        fn write_part(
            &mut self,
            position: usize,
            offset: usize,
            data: &[u8],
        ) -> Result<(), ::edsgen_runtime::SdoAbort> {
            self.stage.write(position, offset, data)
        }
        fn commit_write(
            &mut self,
            position: usize,
            len: usize,
        ) -> Result<(), ::edsgen_runtime::SdoAbort> {
            let value = self.stage.commit(position, len)?;
            LAYOUT.write(&mut self.values, position, value)
        }
        fn abort_write(&mut self, position: usize) {
            self.stage.abort(position)
        }
        fn restore_defaults(
            &mut self,
            indices: ::core::ops::RangeInclusive<u16>,
            node_id: u8,
        ) -> bool {
            LAYOUT.restore_defaults(&mut self.values, &DEFAULTS, node_id, indices);
            true
        }
    }
"##;

/// `Od` with its rustdoc, and `impl Od` up to the end of `Od::new`.
const OD_HEAD: &str = r##"    /// The object dictionary: every entry's value, little-endian, in one byte array laid out
    /// by `LAYOUT`. The application reads and sets entries through their typed addresses in
    /// `od` (`get`/`set`), the protocols through `ObjectDictionary`.
    #[derive(Debug, Clone, PartialEq)]
    pub struct Od {
        values: [u8; IMAGE_SIZE],
        /// An SDO download of a string, octet string or domain until it completes.
        stage: ::edsgen_runtime::support::Stage<STAGE_SIZE>,
    }
    impl Od {
        /// The dictionary with every entry at its default (a DCF's ParameterValue where
        /// given); `$NODEID` defaults are computed from `node_id`.
        pub const fn new(node_id: u8) -> Self {
            let mut od = Od {
                values: [0; IMAGE_SIZE],
                stage: ::edsgen_runtime::support::Stage::new(),
            };
            ::edsgen_runtime::support::unpack_defaults(
                &mut od.values,
                &DEFAULTS,
                node_id,
            );
"##;

/// The rest of `impl Od` (from the end of `Od::new`): the typed `get`, `get_checked` and `set`.
const OD_TAIL: &str = r##"            od
        }
        /// The value of `entry`, a typed address of this dictionary (`od::CONTROLWORD`,
        /// branded `Entry<T, Od>`) of any access: it is here, at its recorded position, with
        /// its type, so the read cannot fail.
        pub fn get<T: ::edsgen_runtime::OdValue + Default, A>(
            &self,
            entry: ::edsgen_runtime::Entry<T, Od, A>,
        ) -> T {
            LAYOUT.get(&self.values, entry).unwrap_or_default()
        }
        /// The value of an address from elsewhere (`Entry::new`, another device's module);
        /// `None` if this dictionary does not hold it with that type.
        pub fn get_checked<T: ::edsgen_runtime::OdValue, D, A>(
            &self,
            entry: ::edsgen_runtime::Entry<T, D, A>,
        ) -> Option<T> {
            LAYOUT.get(&self.values, entry)
        }
        /// Sets `entry` (a typed address from `od`, or from elsewhere) to `value`, checked
        /// like an SDO write (length, BOOLEAN, LowLimit/HighLimit) but not against access
        /// rights: the application keeps its read-only entries current. On error the value
        /// is unchanged.
        pub fn set<T: ::edsgen_runtime::OdValue, D, A>(
            &mut self,
            entry: ::edsgen_runtime::Entry<T, D, A>,
            value: T,
        ) -> Result<(), ::edsgen_runtime::SdoAbort> {
            LAYOUT.set(&mut self.values, entry, &value)
        }
    }
"##;

#[cfg(test)]
mod tests {
    use super::*;

    /// `text` (items at the module's indentation) as `prettyplease` prints it again.
    fn printed_again(text: &str) -> String {
        let module = format!("mod m {{\n{text}}}\n");
        let file: syn::File = syn::parse_str(&module).expect("parses");
        let again = prettyplease::unparse(&file);
        again
            .strip_prefix("mod m {\n")
            .and_then(|rest| rest.strip_suffix("}\n"))
            .expect("one module")
            .to_owned()
    }

    #[test]
    fn the_fixed_items_are_as_prettyplease_prints_them() {
        assert_eq!(printed_again(OD_IMPL), OD_IMPL);
        let od = od_struct();
        assert_eq!(printed_again(&od), od);
    }
}
