//! An object's entries by sub-index: a sorted vector, with the part of a `BTreeMap`'s interface
//! the workspace uses. Most objects have one entry and readers add them in order, so one
//! allocation of the right size holds them (a `BTreeMap` allocates room for eleven).

use std::ops::{Bound, Index, RangeBounds};

use super::SubObject;

/// The entries of one object, in sub-index order, each sub-index at most once.
#[derive(Clone, Default, PartialEq)]
pub struct Subs {
    entries: Vec<(u8, SubObject)>,
}

impl Subs {
    /// No entries.
    pub const fn new() -> Self {
        Subs {
            entries: Vec::new(),
        }
    }

    /// Room for `additional` more entries, so that adding them moves none (an entry is large).
    pub fn reserve(&mut self, additional: usize) {
        self.entries.reserve_exact(additional);
    }

    /// Where `sub` is, or where it would go.
    fn search(&self, sub: u8) -> Result<usize, usize> {
        // Readers add entries in order: the last one is the likeliest place.
        match self.entries.last() {
            Some((last, _)) if *last < sub => Err(self.entries.len()),
            _ => self.entries.binary_search_by_key(&sub, |(s, _)| *s),
        }
    }

    /// Adds or replaces the entry at `sub`; the one it replaces, if any.
    pub fn insert(&mut self, sub: u8, entry: SubObject) -> Option<SubObject> {
        match self.search(sub) {
            Ok(at) => Some(std::mem::replace(&mut self.entries[at].1, entry)),
            Err(at) => {
                self.entries.insert(at, (sub, entry));
                None
            }
        }
    }

    /// The entry at `sub`.
    pub fn get(&self, sub: &u8) -> Option<&SubObject> {
        let at = self.search(*sub).ok()?;
        self.entries.get(at).map(|(_, entry)| entry)
    }

    /// The entry at `sub`, to change.
    pub fn get_mut(&mut self, sub: &u8) -> Option<&mut SubObject> {
        let at = self.search(*sub).ok()?;
        self.entries.get_mut(at).map(|(_, entry)| entry)
    }

    /// Whether there is an entry at `sub`.
    pub fn contains_key(&self, sub: &u8) -> bool {
        self.search(*sub).is_ok()
    }

    /// The number of entries.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether there is no entry.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The sub-indices, in order.
    pub fn keys(&self) -> impl DoubleEndedIterator<Item = &u8> + ExactSizeIterator + Clone {
        self.entries.iter().map(|(sub, _)| sub)
    }

    /// The entries, in sub-index order.
    pub fn values(
        &self,
    ) -> impl DoubleEndedIterator<Item = &SubObject> + ExactSizeIterator + Clone {
        self.entries.iter().map(|(_, entry)| entry)
    }

    /// The entries, in sub-index order, to change.
    pub fn values_mut(
        &mut self,
    ) -> impl DoubleEndedIterator<Item = &mut SubObject> + ExactSizeIterator {
        self.entries.iter_mut().map(|(_, entry)| entry)
    }

    /// Sub-index and entry, in order.
    pub fn iter(
        &self,
    ) -> impl DoubleEndedIterator<Item = (&u8, &SubObject)> + ExactSizeIterator + Clone {
        self.entries.iter().map(|(sub, entry)| (sub, entry))
    }

    /// Sub-index and entry for the sub-indices in `range`, in order.
    pub fn range(
        &self,
        range: impl RangeBounds<u8>,
    ) -> impl DoubleEndedIterator<Item = (&u8, &SubObject)> + ExactSizeIterator + Clone {
        let start = match range.start_bound() {
            Bound::Included(s) => self.entries.partition_point(|(k, _)| k < s),
            Bound::Excluded(s) => self.entries.partition_point(|(k, _)| k <= s),
            Bound::Unbounded => 0,
        };
        let end = match range.end_bound() {
            Bound::Included(e) => self.entries.partition_point(|(k, _)| k <= e),
            Bound::Excluded(e) => self.entries.partition_point(|(k, _)| k < e),
            Bound::Unbounded => self.entries.len(),
        };
        self.entries
            .get(start..end.max(start))
            .unwrap_or_default()
            .iter()
            .map(|(sub, entry)| (sub, entry))
    }

    /// Keeps the entries `keep` is true for.
    pub fn retain(&mut self, mut keep: impl FnMut(&u8, &mut SubObject) -> bool) {
        self.entries.retain_mut(|(sub, entry)| keep(sub, entry));
    }
}

impl std::fmt::Debug for Subs {
    /// As a `BTreeMap` of the same entries prints.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_map().entries(self.iter()).finish()
    }
}

impl Index<&u8> for Subs {
    type Output = SubObject;

    /// The entry at `sub`; panics if there is none, as a `BTreeMap` does.
    fn index(&self, sub: &u8) -> &SubObject {
        match self.get(sub) {
            Some(entry) => entry,
            None => panic!("no entry at sub-index {sub}"),
        }
    }
}

impl<'a> IntoIterator for &'a Subs {
    type Item = (&'a u8, &'a SubObject);
    type IntoIter = std::iter::Map<
        std::slice::Iter<'a, (u8, SubObject)>,
        fn(&'a (u8, SubObject)) -> (&'a u8, &'a SubObject),
    >;

    fn into_iter(self) -> Self::IntoIter {
        self.entries.iter().map(|(sub, entry)| (sub, entry))
    }
}

impl FromIterator<(u8, SubObject)> for Subs {
    /// The entries in sub-index order; a later entry at the same sub-index replaces an earlier.
    fn from_iter<I: IntoIterator<Item = (u8, SubObject)>>(iter: I) -> Self {
        let mut subs = Subs::new();
        for (sub, entry) in iter {
            subs.insert(sub, entry);
        }
        subs
    }
}

#[cfg(test)]
mod tests {
    use super::Subs;
    use crate::model::{Span, SubObject};

    fn entry(sub_index: u8, name: &str) -> SubObject {
        SubObject {
            sub_index,
            name: name.to_owned(),
            data_type: None,
            access: None,
            pdo_mapping: false,
            default: None,
            parameter_value: None,
            low_limit: None,
            high_limit: None,
            obj_flags: 0,
            denotation: None,
            upload_file: None,
            download_file: None,
            span: Span::default(),
            custom: Vec::new(),
            implicit: false,
            key_spans: Default::default(),
            capacity: None,
        }
    }

    #[test]
    fn entries_stay_in_order_and_replace_as_a_map_does() {
        let mut subs = Subs::new();
        assert!(subs.insert(3, entry(3, "c")).is_none());
        assert!(subs.insert(1, entry(1, "a")).is_none());
        assert!(subs.insert(7, entry(7, "e")).is_none());
        assert!(subs.insert(5, entry(5, "d")).is_none());
        let old = subs.insert(3, entry(3, "C")).map(|e| e.name);
        assert_eq!(old.as_deref(), Some("c"));
        assert_eq!(subs.keys().copied().collect::<Vec<_>>(), [1, 3, 5, 7]);
        assert_eq!(
            subs.values().map(|e| e.name.as_str()).collect::<Vec<_>>(),
            ["a", "C", "d", "e"]
        );
        assert_eq!(subs.len(), 4);
        assert_eq!(subs[&5].name, "d");
        assert!(subs.get(&4).is_none() && !subs.contains_key(&0));
        assert_eq!(
            subs.range(2..7).map(|(k, _)| *k).collect::<Vec<_>>(),
            [3, 5]
        );
        assert_eq!(
            subs.range(3..=7).map(|(k, _)| *k).collect::<Vec<_>>(),
            [3, 5, 7]
        );
        assert_eq!(subs.range(..1).count(), 0);
        // A range that ends before it starts is empty (a `BTreeMap` would panic).
        let (from, to) = (6, 2);
        assert_eq!(subs.range(from..to).count(), 0);
        assert_eq!(subs.range(..).next_back().map(|(k, _)| *k), Some(7));
        subs.retain(|k, _| *k != 3);
        assert_eq!(subs.keys().copied().collect::<Vec<_>>(), [1, 5, 7]);
        let collected: Subs = [(9, entry(9, "x")), (2, entry(2, "y")), (9, entry(9, "z"))]
            .into_iter()
            .collect();
        assert_eq!(
            collected
                .iter()
                .map(|(k, e)| (*k, e.name.as_str()))
                .collect::<Vec<_>>(),
            [(2, "y"), (9, "z")]
        );
        assert_eq!(format!("{:?}", Subs::new()), "{}");
    }
}
