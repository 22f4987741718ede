//! Work over a list on every core, results in the list's order: the commands that read many
//! files (`edsgen validate`) print what they found as if they had read them one by one.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::thread;

/// `f` of each item, in the items' order, computed on up to as many threads as there are cores;
/// threads take the next item as they finish one, the heaviest first by `weight` (a file's
/// size, say), so the threads run out of work together, each finishing on a light item.
pub fn map_in_order<T: Sync, R: Send>(
    items: &[T],
    weight: impl Fn(&T) -> u64,
    f: impl Fn(&T) -> R + Sync,
) -> Vec<R> {
    let threads = thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(items.len());
    if threads <= 1 {
        return items.iter().map(f).collect();
    }
    let mut order: Vec<(u64, usize)> = items.iter().map(&weight).zip(0..).collect();
    order.sort_unstable_by(|a, b| b.cmp(a));
    let next = AtomicUsize::new(0);
    let work = || {
        let mut done = Vec::new();
        loop {
            let taken = next.fetch_add(1, Ordering::Relaxed);
            let Some((_, at)) = order.get(taken) else {
                return done;
            };
            let Some(item) = items.get(*at) else {
                return done;
            };
            done.push((*at, f(item)));
        }
    };
    let mut done: Vec<(usize, R)> = thread::scope(|scope| {
        let others: Vec<_> = (1..threads).map(|_| scope.spawn(work)).collect();
        let mut done = work();
        for other in others {
            // A panic in `f` is a bug: it goes on as the panic it was.
            match other.join() {
                Ok(theirs) => done.extend(theirs),
                Err(panic) => std::panic::resume_unwind(panic),
            }
        }
        done
    });
    done.sort_unstable_by_key(|(at, _)| *at);
    done.into_iter().map(|(_, r)| r).collect()
}

#[cfg(test)]
mod tests {
    use super::map_in_order;

    #[test]
    fn results_come_in_the_items_order() {
        let items: Vec<u64> = (0..1000).collect();
        // Weights that reorder the work: the results still come in the items' order.
        let squares = map_in_order(
            &items,
            |n| n % 10,
            |n| {
                // Uneven work, so threads finish out of order.
                if n % 7 == 0 {
                    std::thread::yield_now();
                }
                n * n
            },
        );
        assert_eq!(squares, items.iter().map(|n| n * n).collect::<Vec<_>>());
        assert_eq!(map_in_order(&[] as &[u8], |_| 0, |b| *b), Vec::<u8>::new());
        assert_eq!(map_in_order(&[3u8], |_| 0, |b| *b + 1), vec![4]);
    }
}
