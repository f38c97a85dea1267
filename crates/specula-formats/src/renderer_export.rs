//! A fitted analytic material ([`crate::material_fit`]) written for the renderers that take
//! parameters: a Mitsuba 3 scene, a pbrt-v4 material line and a glTF 2.0 material.
//!
//! - **Mitsuba 3** (`roughconductor`, `roughplastic` with `nonlinear`): the same conductor as
//!   Specula's (`microfacet.rs`: Mitsuba's separable Smith masking) and the same coat lobe, so
//!   the scene's material evaluates as the fit does (`tools/fit_export_check.py`, test
//!   `fit_export_mitsuba`: within 5e-6 for conductors, 1.5 % for the smooth green paint coat).
//!   The coat's base term differs for rough coats: Mitsuba's `roughplastic` lets into the coat
//!   only the light its single-scattering microfacet transmission carries, where Specula's
//!   coat lets in all the light the lobe does not reflect (`1 - E`, energy-conserving,
//!   `clearcoat.rs`); measured at ior 1.49, Mitsuba's base is darker by 0.7 % at alpha 0.008,
//!   1.4 % at 0.05, 3.6 % at 0.1, 11 % at 0.2, 2.2x at 1 ([`mitsuba_warning`]). `ext_ior` is
//!   written as 1 (Mitsuba's default is air's 1.000277).
//! - **pbrt-v4** (`conductor`, `coateddiffuse`, `remaproughness` false so `roughness` is GGX's
//!   alpha): pbrt-v4 uses the height-correlated Smith masking and evaluates its coated diffuse
//!   material by a stochastic random walk through the layer (thickness 0.01, no medium), so its
//!   values differ from the fit's at grazing angles; not checked against pbrt here.
//! - **glTF 2.0** (core metallic-roughness, `KHR_materials_ior`): glTF's roughness is
//!   `sqrt(alpha)` (glTF 2.0 spec, appendix B: `alpha = roughness^2`). A conductor is metallic
//!   with base colour its normal-incidence reflectance `F(0)` (glTF's Schlick curve from there
//!   to white at grazing stands for the exact conductor Fresnel). The coat is glTF's
//!   dielectric (a GGX lobe of the given index mixed by Fresnel over a Lambertian base): its
//!   base colour is chosen so that the diffuse part at normal incidence and view equals the
//!   fit's, `rho_gltf (1 - F(0)) / pi = f_coat(n, n) - f_coat without base(n, n)`.

use specula_core::materials::clearcoat::ClearCoat;
use specula_core::materials::conductor::RoughConductor;
use specula_core::materials::microfacet::IsotropicCosines;
use specula_core::materials::{Base, Distribution, Material};
use specula_core::scattering::fresnel;
use specula_core::Rgb;
use std::fmt::Write;

/// Coats rougher than this are darker in Mitsuba 3's `roughplastic` than in the fit by more
/// than about 1.5 % (module documentation).
pub const MITSUBA_COAT_ALPHA_LIMIT: f64 = 0.05;

/// A warning for the Mitsuba export of `material`, where Mitsuba's `roughplastic` does not
/// reproduce it: a coat rougher than [`MITSUBA_COAT_ALPHA_LIMIT`].
pub fn mitsuba_warning(material: &Material) -> Option<String> {
    match &material.base {
        Base::ClearCoat(c) if c.alpha() > MITSUBA_COAT_ALPHA_LIMIT => Some(format!(
            "the coat's alpha {:.3} is above {MITSUBA_COAT_ALPHA_LIMIT}: Mitsuba's roughplastic, single-scattering, renders its base darker than the fit (4 % at alpha 0.1, 11 % at 0.2, 2.2x at 1)",
            c.alpha()
        )),
        _ => None,
    }
}

/// Why a material cannot be written for a renderer.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// The material (named) has a scratch lobe, which no renderer's analytic material has.
    #[error(
        "material '{0}' has a scratch lobe, which none of the renderers' analytic materials has"
    )]
    Scratched(String),
    /// The material (named) uses the Beckmann distribution; the renderer (named) is GGX only.
    #[error("material '{0}' uses the Beckmann distribution; {1} materials are GGX only")]
    NotGgx(String, &'static str),
}

/// The base of a material without scratches.
fn plain_base(material: &Material) -> Result<&Base, ExportError> {
    match material.scratch {
        Some(_) => Err(ExportError::Scratched(material.name.clone())),
        None => Ok(&material.base),
    }
}

/// The three channels, each printed to round-trip exactly.
fn rgb_list(c: Rgb, separator: &str) -> String {
    format!("{}{separator}{}{separator}{}", c.x, c.y, c.z)
}

/// The Mitsuba 3 `<bsdf>` element of `material` (GGX or Beckmann).
pub fn mitsuba_bsdf(material: &Material) -> Result<String, ExportError> {
    let mut xml = String::new();
    match plain_base(material)? {
        Base::Conductor(c) => {
            let _ = writeln!(
                xml,
                r#"<bsdf type="roughconductor" id="{}">"#,
                material.name
            );
            mitsuba_roughness(&mut xml, c.distribution(), c.alpha());
            let _ = writeln!(
                xml,
                r#"    <rgb name="eta" value="{}"/>"#,
                rgb_list(c.eta, ", ")
            );
            let _ = writeln!(
                xml,
                r#"    <rgb name="k" value="{}"/>"#,
                rgb_list(c.k, ", ")
            );
        }
        Base::ClearCoat(c) => {
            let _ = writeln!(xml, r#"<bsdf type="roughplastic" id="{}">"#, material.name);
            mitsuba_roughness(&mut xml, c.distribution(), c.alpha());
            let _ = writeln!(xml, r#"    <float name="int_ior" value="{}"/>"#, c.ior);
            let _ = writeln!(xml, r#"    <float name="ext_ior" value="1"/>"#);
            let _ = writeln!(
                xml,
                r#"    <rgb name="diffuse_reflectance" value="{}"/>"#,
                rgb_list(c.base_color, ", ")
            );
            let _ = writeln!(xml, r#"    <boolean name="nonlinear" value="true"/>"#);
        }
    }
    xml.push_str("</bsdf>\n");
    Ok(xml)
}

fn mitsuba_roughness(xml: &mut String, distribution: Distribution, alpha: f64) {
    let _ = writeln!(
        xml,
        r#"    <string name="distribution" value="{}"/>"#,
        distribution.label()
    );
    let _ = writeln!(xml, r#"    <float name="alpha" value="{alpha}"/>"#);
}

/// A Mitsuba 3 scene: a unit sphere with `material` (its first shape, so
/// `scene.shapes()[0].bsdf()` is the material) under a constant white environment, seen by a
/// perspective camera from 4 units, path traced. Render with `mitsuba scene.xml`
/// (an RGB variant, e.g. `-m scalar_rgb`).
pub fn mitsuba_scene(material: &Material) -> Result<String, ExportError> {
    let bsdf = mitsuba_bsdf(material)?;
    let indented: String = bsdf.lines().map(|l| format!("        {l}\n")).collect();
    Ok(format!(
        r#"<scene version="3.0.0">
    <!-- Written by specula fit: the analytic material fitted to '{name}'. -->
    <integrator type="path"/>
    <sensor type="perspective">
        <float name="fov" value="30"/>
        <transform name="to_world">
            <lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/>
        </transform>
        <film type="hdrfilm">
            <integer name="width" value="512"/>
            <integer name="height" value="512"/>
        </film>
        <sampler type="independent">
            <integer name="sample_count" value="64"/>
        </sampler>
    </sensor>
    <shape type="sphere">
{indented}    </shape>
    <emitter type="constant">
        <rgb name="radiance" value="1, 1, 1"/>
    </emitter>
</scene>
"#,
        name = material.name
    ))
}

/// The pbrt-v4 `Material` directive of `material` (GGX only, pbrt's Trowbridge-Reitz).
pub fn pbrt_material(material: &Material) -> Result<String, ExportError> {
    let (distribution, alpha) = match plain_base(material)? {
        Base::Conductor(c) => (c.distribution(), c.alpha()),
        Base::ClearCoat(c) => (c.distribution(), c.alpha()),
    };
    if distribution != Distribution::Ggx {
        return Err(ExportError::NotGgx(material.name.clone(), "pbrt-v4"));
    }
    let roughness = format!(r#""float roughness" [ {alpha} ] "bool remaproughness" false"#);
    Ok(match &material.base {
        Base::Conductor(c) => format!(
            "# specula fit: GGX conductor fitted to '{}'\nMaterial \"conductor\" {roughness}\n    \"rgb eta\" [ {} ] \"rgb k\" [ {} ]\n",
            material.name,
            rgb_list(c.eta, " "),
            rgb_list(c.k, " ")
        ),
        Base::ClearCoat(c) => format!(
            "# specula fit: GGX dielectric coat over a diffuse base fitted to '{}'\nMaterial \"coateddiffuse\" {roughness}\n    \"float eta\" [ {} ] \"rgb reflectance\" [ {} ] \"float thickness\" [ 0.01 ]\n",
            material.name,
            c.ior,
            rgb_list(c.base_color, " ")
        ),
    })
}

/// A glTF 2.0 JSON document holding `material` as its one material (GGX only; the mapping is
/// in the module documentation).
pub fn gltf_document(material: &Material) -> Result<String, ExportError> {
    let gltf_material = match plain_base(material)? {
        Base::Conductor(c) => gltf_conductor(&material.name, c)?,
        Base::ClearCoat(c) => gltf_coat(&material.name, c)?,
    };
    let mut document = serde_json::json!({
        "asset": { "version": "2.0", "generator": "specula fit" },
        "materials": [gltf_material],
    });
    if matches!(material.base, Base::ClearCoat(_)) {
        document["extensionsUsed"] = serde_json::json!(["KHR_materials_ior"]);
    }
    Ok(serde_json::to_string_pretty(&document).expect("a JSON value serialises") + "\n")
}

fn require_ggx(name: &str, distribution: Distribution) -> Result<(), ExportError> {
    match distribution {
        Distribution::Ggx => Ok(()),
        Distribution::Beckmann => Err(ExportError::NotGgx(name.to_string(), "glTF")),
    }
}

fn unit_rgba(c: Rgb) -> [f64; 4] {
    let c = c.clamp(Rgb::ZERO, Rgb::ONE);
    [c.x, c.y, c.z, 1.0]
}

fn gltf_conductor(name: &str, c: &RoughConductor) -> Result<serde_json::Value, ExportError> {
    require_ggx(name, c.distribution())?;
    let f0 = fresnel::conductor_rgb(1.0, c.eta, c.k);
    Ok(serde_json::json!({
        "name": name,
        "pbrMetallicRoughness": {
            "baseColorFactor": unit_rgba(f0),
            "metallicFactor": 1.0,
            "roughnessFactor": c.alpha().sqrt(),
        },
    }))
}

fn gltf_coat(name: &str, c: &ClearCoat) -> Result<serde_json::Value, ExportError> {
    require_ggx(name, c.distribution())?;
    let normal = IsotropicCosines {
        cos_h: 1.0,
        cos_d: 1.0,
        cos_i: 1.0,
        cos_o: 1.0,
    };
    let specular_only = ClearCoat::new(c.distribution(), c.alpha(), c.ior, Rgb::ZERO);
    let diffuse = c.eval_cosines(normal) - specular_only.eval_cosines(normal);
    let f0 = fresnel::dielectric(1.0, c.ior);
    let base = diffuse * std::f64::consts::PI / (1.0 - f0);
    Ok(serde_json::json!({
        "name": name,
        "pbrMetallicRoughness": {
            "baseColorFactor": unit_rgba(base),
            "metallicFactor": 0.0,
            "roughnessFactor": c.alpha().sqrt(),
        },
        "extensions": { "KHR_materials_ior": { "ior": c.ior } },
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use specula_core::materials::preset;

    #[test]
    fn gltf_roughness_is_the_square_root_of_alpha() {
        let chrome = preset("chrome").unwrap();
        let doc: serde_json::Value =
            serde_json::from_str(&gltf_document(&chrome).unwrap()).unwrap();
        let pbr = &doc["materials"][0]["pbrMetallicRoughness"];
        let Base::Conductor(c) = &chrome.base else {
            panic!("chrome is a conductor")
        };
        let roughness = pbr["roughnessFactor"].as_f64().unwrap();
        assert!((roughness * roughness - c.alpha()).abs() < 1e-12);
        assert_eq!(pbr["metallicFactor"].as_f64(), Some(1.0));
    }

    #[test]
    fn gltf_coat_keeps_the_diffuse_albedo_at_normal_incidence() {
        // Far from the lobe only the base is left; glTF's Lambertian (1 - F0) rho / pi at
        // normal incidence must equal the coat's base term there.
        let paint = preset("green-paint").unwrap();
        let doc: serde_json::Value = serde_json::from_str(&gltf_document(&paint).unwrap()).unwrap();
        let m = &doc["materials"][0];
        let ior = m["extensions"]["KHR_materials_ior"]["ior"]
            .as_f64()
            .unwrap();
        let g = m["pbrMetallicRoughness"]["baseColorFactor"][1]
            .as_f64()
            .unwrap();
        let Base::ClearCoat(c) = &paint.base else {
            panic!("the paint is a coat")
        };
        let rho = c.base_color.y;
        // Smooth-coat limit: (1 - F0)^2 / eta^2 rho / (1 - rho r_int); r_int between 0.5 and 0.7.
        let f0 = fresnel::dielectric(1.0, ior);
        let low = (1.0 - f0) / (ior * ior) * rho / (1.0 - 0.5 * rho);
        let high = (1.0 - f0) / (ior * ior) * rho / (1.0 - 0.7 * rho);
        assert!((low..high).contains(&g), "{low} {g} {high}");
    }

    #[test]
    fn scratched_materials_are_refused() {
        let scratched = preset("silver-925-scratched").unwrap();
        assert!(matches!(
            mitsuba_scene(&scratched),
            Err(ExportError::Scratched(_))
        ));
        assert!(matches!(
            pbrt_material(&scratched),
            Err(ExportError::Scratched(_))
        ));
    }
}
