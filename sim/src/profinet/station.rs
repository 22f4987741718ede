//! What a simulated device says about itself, from its GSDML: VendorID, DeviceID, the default
//! access point's `DNS_CompatibleName` (the name of station it starts with), a type of station
//! (the vendor and product family), and its instance.

use edsgen_model::model::Profinet;

use super::dcp::Station;
use super::wire::Mac;

/// The station of the GSDML's default access point on an interface with `mac`.
pub fn from_gsdml(pn: &Profinet, mac: Mac) -> Station {
    let dap = pn.access_points.first();
    let family = pn
        .family
        .as_ref()
        .map(|(_, product)| product.clone())
        .filter(|p| !p.is_empty());
    let type_of_station = match (&pn.vendor_name, family) {
        (Some(v), Some(f)) => format!("{v} {f}"),
        (Some(v), None) => v.clone(),
        (None, Some(f)) => f,
        (None, None) => "PROFINET device".to_owned(),
    };
    Station {
        mac,
        name_of_station: dap
            .and_then(|d| d.dns_compatible_name.clone())
            .unwrap_or_default(),
        ip: [[0; 4]; 3],
        vendor_id: pn.vendor_id.as_ref().map_or(0, |v| v.value),
        device_id: pn.device_id.as_ref().map_or(0, |v| v.value),
        type_of_station,
        instance: (0, 1),
    }
}
