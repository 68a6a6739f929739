//! Hostile and unusual robot files: every one ends in a clear error (or the right robot),
//! never a crash, a hang or unbounded memory. Each test failed before its fix.

use screwkit_model::{input, urdf, xacro, Chain, ErrorKind, ModelError, XacroOptions};

fn xacro_doc(body: &str) -> String {
    format!(
        "<?xml version=\"1.0\"?>\n<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n{body}\n</robot>\n"
    )
}

fn expand(text: &str) -> Result<String, ModelError> {
    xacro::expand_str(
        text,
        "t.xacro",
        std::path::Path::new("."),
        &XacroOptions::default(),
    )
}

/// The value a `${…}` expression gives, as text (through a link name).
fn eval(expr: &str) -> Result<String, ModelError> {
    let out = expand(&xacro_doc(&format!(
        "<xacro:property name=\"v\" value=\"${{{expr}}}\"/><link name=\"${{v}}\"/>"
    )))?;
    let start = out.find("<link name=\"").expect("a link") + "<link name=\"".len();
    let end = start + out[start..].find('"').expect("closing quote");
    Ok(out[start..end]
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&amp;", "&"))
}

fn err_text(r: Result<String, ModelError>) -> String {
    r.expect_err("must fail").to_string()
}

// ---- 1. Recursion -----------------------------------------------------------------------------

#[test]
fn deeply_nested_parentheses_are_an_error_not_a_stack_overflow() {
    let e = err_text(eval(&format!("{}1{}", "(".repeat(5000), ")".repeat(5000))));
    assert!(
        e.contains("nested more than") && e.contains("t.xacro:"),
        "{e}"
    );
    // Modest nesting still works.
    assert_eq!(
        eval(&format!("{}1{}", "(".repeat(150), ")".repeat(150))).unwrap(),
        "1"
    );
    let e = err_text(eval(&format!("{}1", "-".repeat(5000))));
    assert!(e.contains("nested more than"), "{e}");
    let e = err_text(eval(&format!("{}True", "not ".repeat(5000))));
    assert!(e.contains("nested more than"), "{e}");
}

#[test]
fn deeply_nested_elements_are_an_error() {
    let nested = format!("{}{}", "<a>".repeat(10_000), "</a>".repeat(10_000));
    let e = err_text(expand(&xacro_doc(&nested)));
    assert!(e.contains("nested more than 256 levels"), "{e}");
    let urdf = format!("<robot name=\"r\"><link name=\"a\"/>{nested}</robot>");
    let e = urdf::load_str(&urdf, "t.urdf").unwrap_err().to_string();
    assert!(
        e.starts_with("t.urdf: ") && e.contains("nested more than 256 levels"),
        "{e}"
    );
    // A million levels: the check itself must not recurse.
    let deep = format!(
        "<robot>{}{}</robot>",
        "<a>".repeat(1_000_000),
        "</a>".repeat(1_000_000)
    );
    let e = urdf::load_str(&deep, "t.urdf").unwrap_err().to_string();
    assert!(e.contains("nested more than"), "{e}");
}

#[test]
fn a_long_chain_of_properties_is_an_error() {
    let mut body = String::from("<xacro:property name=\"p0\" value=\"1\"/>\n");
    for i in 1..2000 {
        body.push_str(&format!(
            "<xacro:property name=\"p{i}\" value=\"${{p{} + 1}}\"/>\n",
            i - 1
        ));
    }
    body.push_str("<link name=\"${p1999}\"/>");
    let e = err_text(expand(&xacro_doc(&body)));
    assert!(e.contains("nested more than"), "{e}");
    // 100 levels are fine (and give the right number).
    let mut body = String::from("<xacro:property name=\"p0\" value=\"1\"/>\n");
    for i in 1..100 {
        body.push_str(&format!(
            "<xacro:property name=\"p{i}\" value=\"${{p{} + 1}}\"/>\n",
            i - 1
        ));
    }
    body.push_str("<link name=\"l${p99}\"/>");
    assert!(expand(&xacro_doc(&body)).unwrap().contains("name=\"l100\""));
}

// ---- 2. Amplification -------------------------------------------------------------------------

#[test]
fn entity_amplification_is_refused() {
    let big = "x".repeat(50_000);
    let uses = "&e;".repeat(50_000);
    let text = format!(
        "<?xml version=\"1.0\"?><!DOCTYPE robot [<!ENTITY e \"{big}\">]><robot name=\"r\"><link name=\"a\"/><gazebo>{uses}</gazebo></robot>"
    );
    let e = urdf::load_str(&text, "t.urdf").unwrap_err();
    assert!(
        e.to_string()
            .contains("entities expand to more than 1024 KiB"),
        "{e}"
    );
    // Nested ("billion laughs"), in an attribute.
    let mut dtd = String::from("<!ENTITY l0 \"lol\">");
    for i in 1..10 {
        dtd.push_str(&format!(
            "<!ENTITY l{i} \"{}\">",
            format!("&l{};", i - 1).repeat(10)
        ));
    }
    let text = format!("<!DOCTYPE robot [{dtd}]><robot name=\"&l9;\"><link name=\"a\"/></robot>");
    let e = urdf::load_str(&text, "t.urdf").unwrap_err();
    assert!(e.to_string().contains("entities expand"), "{e}");
    // A small entity is fine.
    let text =
        "<!DOCTYPE robot [<!ENTITY n \"arm\">]><robot name=\"&n;\"><link name=\"a\"/></robot>";
    assert_eq!(urdf::load_str(text, "t.urdf").unwrap().name, "arm");
}

#[test]
fn doubling_properties_stop_at_the_size_limit() {
    let mut body =
        String::from("<xacro:property name=\"p0\" value=\"xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx\"/>\n");
    for i in 1..32 {
        body.push_str(&format!(
            "<xacro:property name=\"p{i}\" value=\"${{p{0}}}${{p{0}}}\"/>\n",
            i - 1
        ));
    }
    body.push_str("<link name=\"${p31}\"/>");
    let e = err_text(expand(&xacro_doc(&body)));
    assert!(e.contains("longer than 64 MiB"), "{e}");
    // The same through `+`.
    let body = body.replace("}${p", " + p");
    let e = err_text(expand(&xacro_doc(&body)));
    assert!(e.contains("longer than 64 MiB"), "{e}");
}

#[test]
fn exponential_macro_fan_out_stops() {
    // m0 emits a link; m{i} calls m{i-1} twice: 2^40 links.
    let mut body = String::from("<xacro:macro name=\"m0\"><a/></xacro:macro>\n");
    for i in 1..40 {
        body.push_str(&format!(
            "<xacro:macro name=\"m{i}\"><xacro:m{0}/><xacro:m{0}/></xacro:macro>\n",
            i - 1
        ));
    }
    body.push_str("<xacro:m39/>");
    let e = err_text(expand(&xacro_doc(&body)));
    assert!(e.contains("steps") || e.contains("larger than"), "{e}");
    // Without output (a false condition inside), the work limit still ends it.
    let body = body.replace("<a/>", "<xacro:if value=\"false\"><a/></xacro:if>");
    let e = err_text(expand(&xacro_doc(&body)));
    assert!(e.contains("steps"), "{e}");
}

// ---- 3. Panics --------------------------------------------------------------------------------

#[test]
fn integer_overflow_is_an_error() {
    for expr in [
        "(-9223372036854775807 - 1) // -1",
        "abs(-9223372036854775807 - 1)",
        "-(-9223372036854775807 - 1)",
        "9223372036854775807 + 1",
        "2 ** 64",
        "99999999999999999999",
        "int(1e300)",
    ] {
        let e = err_text(eval(expr));
        assert!(e.contains("beyond 64 bits"), "{expr}: {e}");
    }
    assert_eq!(eval("(-9223372036854775807 - 1) % -1").unwrap(), "0");
    assert_eq!(eval("-7 // 2").unwrap(), "-4");
    assert_eq!(eval("-7 % 3").unwrap(), "2");
    assert_eq!(eval("7 % -3").unwrap(), "-2");
    assert_eq!(eval("(-1) ** 1000001").unwrap(), "-1");
    assert_eq!(eval("2 ** -1").unwrap(), "0.5");
}

#[test]
fn a_namespaced_multibyte_prefix_inside_a_joint() {
    let text = r#"<robot name="r" xmlns:ü="urn:u"><link name="a"/><link name="b"/>
      <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
        <ü:limit lower="-5" upper="5"/>
        <limit ü:x="1" lower="-1" upper="1" effort="1" velocity="1"/>
      </joint></robot>"#;
    let tree = urdf::load_str(text, "t.urdf").unwrap();
    let chain = Chain::from_tree(&tree, None, None).unwrap();
    assert_eq!(
        (chain.variables[0].lower, chain.variables[0].upper),
        (-1.0, 1.0)
    );
}

// ---- 5. Endless inputs ------------------------------------------------------------------------

#[test]
#[cfg(unix)]
fn dev_zero_as_a_robot_or_an_include() {
    let e = urdf::load_file("/dev/zero").unwrap_err();
    assert!(matches!(e.kind, ErrorKind::TooLarge(_)), "{e}");
    assert!(
        e.to_string()
            .starts_with("/dev/zero: too large: more than 64 MiB"),
        "{e}"
    );
    let text = xacro_doc("<xacro:include filename=\"/dev/zero\"/>");
    let e = err_text(expand(&text));
    assert!(
        e.contains("t.xacro:3") && e.contains("more than 64 MiB"),
        "{e}"
    );
    let e = urdf::load_file("/").unwrap_err();
    assert!(e.to_string().contains("directory"), "{e}");
    assert_eq!(input::MAX_FILE_BYTES, 64 << 20);
}

// ---- 10. Foreign namespaces, injected markup --------------------------------------------------

#[test]
fn foreign_namespace_elements_are_not_urdf() {
    let text = r#"<robot name="r" xmlns:u="urn:u"><link name="a"/><link name="b"/><u:link name="c"/>
      <joint name="j" type="fixed"><parent link="a"/><child link="b"/>
        <u:origin xyz="5 5 5"/><origin xyz="1 0 0"/></joint>
      <u:joint name="k" type="fixed"><parent link="b"/><child link="c"/></u:joint></robot>"#;
    let tree = urdf::load_str(text, "t.urdf").unwrap();
    assert_eq!(tree.links.len(), 2);
    assert_eq!(tree.joints.len(), 1);
    assert_eq!(tree.joints[0].origin_xyz, [1.0, 0.0, 0.0]);
    // The same through xacro.
    let x = text
        .replace(
            "<robot name=\"r\"",
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\"",
        )
        .replace("xyz=\"1 0 0\"", "xyz=\"${1} 0 0\"");
    let tree = urdf::load_str(&x, "t.xacro").unwrap();
    assert_eq!(tree.joints.len(), 1);
    assert_eq!(tree.joints[0].origin_xyz, [1.0, 0.0, 0.0]);
}

#[test]
fn element_and_attribute_names_cannot_inject_markup() {
    let inject = "link name=&quot;evil&quot;/&gt;&lt;link name=&quot;x";
    let e = err_text(expand(&xacro_doc(&format!(
        "<xacro:element xacro:name=\"{inject}\"/>"
    ))));
    assert!(e.contains("not an XML name"), "{e}");
    let e = err_text(expand(&xacro_doc(&format!(
        "<link name=\"a\"><xacro:attribute name=\"{inject}\" value=\"1\"/></link>"
    ))));
    assert!(e.contains("not an XML name"), "{e}");
    // Values are escaped: markup in a value stays a value.
    let out = expand(&xacro_doc(&format!(
        "<link name=\"a\"><xacro:attribute name=\"type\" value=\"{inject}\"/></link>"
    )))
    .unwrap();
    assert_eq!(out.matches("<link").count(), 1, "{out}");
}

// ---- 11. Python's semantics -------------------------------------------------------------------

#[test]
fn expressions_follow_python() {
    // Only the chosen branch is evaluated.
    assert_eq!(eval("(1/0) if 0 != 0 else 7").unwrap(), "7");
    assert_eq!(eval("5 if 1 else 1/0").unwrap(), "5");
    assert!(err_text(eval("(1/0) if 1 else 0")).contains("division by zero"));
    assert_eq!(eval("0 and 1/0").unwrap(), "0");
    assert_eq!(eval("1 or 1/0").unwrap(), "1");
    assert_eq!(eval("2 and 3").unwrap(), "3");
    // Strings are truthy when not empty.
    assert_eq!(eval("'arm' if 'x' else 'robot'").unwrap(), "arm");
    assert_eq!(eval("'arm' if '' else 'robot'").unwrap(), "robot");
    assert_eq!(eval("not ''").unwrap(), "True");
    assert_eq!(eval("'' or 'dflt'").unwrap(), "dflt");
    // int/floor/round of NaN and infinity are errors, as in Python.
    for expr in ["int(nan)", "int(inf)", "floor(nan)", "round(inf)"] {
        assert!(err_text(eval(expr)).contains("cannot convert"), "{expr}");
    }
    // Rounding of the exact binary value, halves to even.
    assert_eq!(eval("round(2.675, 2)").unwrap(), "2.67");
    assert_eq!(eval("round(0.125, 2)").unwrap(), "0.12");
    assert_eq!(eval("round(2.5)").unwrap(), "2");
    assert_eq!(eval("round(-0.5)").unwrap(), "0");
    assert_eq!(eval("round(1250, -2)").unwrap(), "1200");
    // Number text as Python's str().
    for (expr, want) in [
        ("1e-7", "1e-07"),
        ("0.0001", "0.0001"),
        ("0.00001", "1e-05"),
        ("1e16", "1e+16"),
        ("1e15", "1000000000000000.0"),
        ("1.5e300", "1.5e+300"),
        ("-2.5e-10", "-2.5e-10"),
        ("0.1 + 0.2", "0.30000000000000004"),
        ("float('inf')", "inf"),
        ("-0.0", "-0.0"),
        ("str(1/3)", "0.3333333333333333"),
        ("123456789.125", "123456789.125"),
    ] {
        assert_eq!(eval(expr).unwrap(), want, "{expr}");
    }
    // A property's text: underscores keep it text, nan/inf read as floats.
    let out = expand(&xacro_doc(
        "<xacro:property name=\"a\" value=\"1_0\"/><xacro:property name=\"b\" value=\"nan\"/><link name=\"${a}${b != b}\"/>",
    ))
    .unwrap();
    assert!(out.contains("name=\"1_0True\""), "{out}");
}

// ---- 12. Linear time --------------------------------------------------------------------------

#[test]
fn many_elements_and_attributes_in_linear_time() {
    // 40,000 elements (7.5 s before: each line number was found from the file's start):
    // well under a second now. (Attributes: at most 1,000 per element, see below.)
    let body: String = (0..40_000).map(|i| format!("<e{i}/>\n")).collect();
    let out = expand(&xacro_doc(&format!(
        "<link name=\"a\"/>{body}<bad x=\"${{nope}}\"/>"
    )));
    let e = out.unwrap_err().to_string();
    assert!(e.contains("t.xacro:40003"), "{e}");
    let attrs: String = (0..999).map(|i| format!(" a{i}=\"${{{i}}}\"")).collect();
    let out = expand(&xacro_doc(&format!("<link name=\"a\"{attrs}/>"))).unwrap();
    assert!(out.contains("a998=\"998\""));
}

// ---- 14. New users' files ---------------------------------------------------------------------

#[test]
fn quoted_macro_defaults_with_spaces() {
    let out = expand(&xacro_doc(
        r#"<xacro:macro name="m" params="name xyz:='0 0 0' rpy:=&quot;0 0.5 0&quot; k:=1">
             <link name="${name}_${k}"><origin xyz="${xyz}" rpy="${rpy}"/></link>
           </xacro:macro>
           <xacro:m name="a"/><xacro:m name="b" xyz="1 2 3" k="2"/>"#,
    ))
    .unwrap();
    assert!(out.contains("<link name=\"a_1\">"), "{out}");
    assert!(out.contains("xyz=\"0 0 0\" rpy=\"0 0.5 0\""), "{out}");
    assert!(
        out.contains("<link name=\"b_2\">") && out.contains("xyz=\"1 2 3\""),
        "{out}"
    );
    let e = err_text(expand(&xacro_doc(
        r#"<xacro:macro name="m" params="a:='0 0"/>"#,
    )));
    assert!(e.contains("unclosed quote"), "{e}");
}

#[test]
fn relative_package_paths_from_another_folder() {
    // A package folder, and the xacro file elsewhere; the package path relative to the cwd
    // (the crate's folder when tests run).
    let root = std::env::temp_dir().join(format!("sk-relpkg-{}", std::process::id()));
    let pkg = root.join("pkgs/mypkg/urdf");
    std::fs::create_dir_all(&pkg).unwrap();
    std::fs::create_dir_all(root.join("robots")).unwrap();
    std::fs::write(
        pkg.join("part.xacro"),
        "<robot xmlns:xacro=\"http://www.ros.org/wiki/xacro\"><link name=\"from_pkg\"/></robot>",
    )
    .unwrap();
    let main = root.join("robots/main.xacro");
    std::fs::write(
        &main,
        xacro_doc("<xacro:include filename=\"$(find mypkg)/urdf/part.xacro\"/>"),
    )
    .unwrap();
    let cwd = std::env::current_dir().unwrap();
    let rel = pathdiff(&root.join("pkgs"), &cwd);
    let opts = XacroOptions {
        package_paths: vec![rel.clone()],
        args: vec![],
    };
    assert!(rel.is_relative(), "{}", rel.display());
    let out = xacro::expand_file(&main, &opts).unwrap_or_else(|e| panic!("{e}"));
    assert!(out.contains("from_pkg"), "{out}");
    let _ = std::fs::remove_dir_all(&root);
}

/// `to` written relative to `from` (both absolute).
fn pathdiff(to: &std::path::Path, from: &std::path::Path) -> std::path::PathBuf {
    let up = from.components().count() - 1;
    let mut p = std::path::PathBuf::new();
    for _ in 0..up {
        p.push("..");
    }
    p.join(to.strip_prefix("/").unwrap())
}

#[test]
fn too_many_attributes_on_one_element() {
    let attrs: String = (0..100_000).map(|i| format!(" a{i}=\"{i}\"")).collect();
    let e = urdf::load_str(
        &format!("<robot name=\"r\">\n<link name=\"a\"{attrs}/></robot>"),
        "t.urdf",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("more than 1000 attributes on the element at line 2"),
        "{e}"
    );
    // Comments, CDATA and a DTD with '>' inside do not confuse the scan.
    let text = "<!DOCTYPE robot [<!ENTITY n \"a>b\">]><robot name=\"r\"><!-- <x a=1 b=2> --><link name=\"a\"><![CDATA[ <y c=\"=\"> ]]></link></robot>";
    assert_eq!(urdf::load_str(text, "t.urdf").unwrap().links.len(), 1);
}

#[test]
fn an_included_file_passes_the_same_checks() {
    let dir = std::env::temp_dir().join(format!("sk-incl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let big = "x".repeat(50_000);
    let uses = "&e;".repeat(50_000);
    std::fs::write(
        dir.join("bomb.xacro"),
        format!("<!DOCTYPE robot [<!ENTITY e \"{big}\">]><robot xmlns:xacro=\"http://www.ros.org/wiki/xacro\"><link name=\"a\">{uses}</link></robot>"),
    )
    .unwrap();
    // An undeclared prefix in the include too (the path that declares it on the fly).
    let attrs: String = (0..5000).map(|i| format!(" a{i}=\"1\"")).collect();
    std::fs::write(
        dir.join("wide.xacro"),
        format!("<robot><xacro:property name=\"p\" value=\"1\"/><link name=\"b\"{attrs}/></robot>"),
    )
    .unwrap();
    for (file, says) in [
        ("bomb.xacro", "entities expand"),
        ("wide.xacro", "more than 1000 attributes"),
    ] {
        let main = xacro_doc(&format!("<xacro:include filename=\"{file}\"/>"));
        let e = xacro::expand_str(&main, "t.xacro", &dir, &XacroOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains(says), "{file}: {e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

// ---- Inertials ------------------------------------------------------------------------------

#[test]
fn link_inertials_are_read_and_bad_ones_name_the_link() {
    let robot = |inertial: &str| {
        format!(
            "<robot name=\"r\"><link name=\"base\"/><link name=\"arm\">{inertial}</link>\
             <joint name=\"j\" type=\"continuous\"><parent link=\"base\"/><child link=\"arm\"/></joint></robot>"
        )
    };
    let tree = urdf::load_str(
        &robot("<inertial><origin xyz=\"0.1 -0.2 0.3\" rpy=\"0 1 0\"/><mass value=\"2.5\"/></inertial>"),
        "t.urdf",
    )
    .unwrap();
    let arm = tree.link("arm").unwrap();
    let i = tree.inertials[arm].expect("the arm's inertial");
    assert_eq!((i.mass, i.com), (2.5, [0.1, -0.2, 0.3]));
    assert!(tree.inertials[tree.link("base").unwrap()].is_none());
    for (inertial, words) in [
        (
            "<inertial><mass value=\"-1\"/></inertial>",
            "mass -1 is not a finite number ≥ 0",
        ),
        (
            "<inertial><mass value=\"nan\"/></inertial>",
            "is not a finite number",
        ),
        (
            "<inertial><mass value=\"1 2\"/></inertial>",
            "expected 1 number(s)",
        ),
        (
            "<inertial><mass value=\"x\"/></inertial>",
            "\"x\" is not a number",
        ),
        (
            "<inertial><origin xyz=\"0 0\"/><mass value=\"1\"/></inertial>",
            "expected 3 number(s)",
        ),
        (
            "<inertial><origin xyz=\"0 inf 0\"/><mass value=\"1\"/></inertial>",
            "not finite",
        ),
        ("<inertial><inertia ixx=\"1\"/></inertial>", "no <mass"),
    ] {
        let e = urdf::load_str(&robot(inertial), "t.urdf")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("t.urdf: ") && e.contains("link \"arm\"") && e.contains(words),
            "{e} (wanted {words})"
        );
    }
}

/// MuJoCo's `balanceinertia`: principal moments that break A + B ≥ C all become their mean
/// (tr / 3), whatever the tensor's orientation; a rigid body's inertial is left as it is.
#[test]
fn balancing_sets_impossible_moments_to_their_mean() {
    let at = |inertia: [f64; 6]| screwkit_model::Inertial {
        mass: 2.0,
        com: [0.1, 0.0, 0.0],
        inertia,
    };
    // diag(1, 0.2, 0.3): 0.2 + 0.3 < 1.
    let bad = at([1.0, 0.0, 0.0, 0.2, 0.0, 0.3]);
    assert!(bad.problem().unwrap().contains("triangle inequality"));
    let b = bad.balanced();
    assert_eq!(b.inertia, [0.5, 0.0, 0.0, 0.5, 0.0, 0.5]);
    assert_eq!((b.mass, b.com), (bad.mass, bad.com));
    assert!(b.problem().is_none());
    // The same moments turned (off-diagonal entries): the mean of the trace, 0.5.
    let turned = at([0.9, 0.2, 0.1, 0.35, 0.05, 0.25]);
    assert!(turned.problem().is_some());
    assert!((turned.balanced().inertia[0] - 0.5).abs() < 1e-15);
    let good = at([0.3, 0.01, 0.0, 0.2, 0.0, 0.4]);
    assert!(good.problem().is_none());
    assert_eq!(good.balanced(), good);
}

/// A joint's `<dynamics damping friction>` (URDF) and `armature`, `damping`, `frictionloss`
/// (MJCF, through default classes) are read; zero when the file says nothing.
#[test]
fn joint_damping_and_armature_are_read() {
    let tree = urdf::load_str(
        "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/><link name=\"c\"/>\
         <joint name=\"j\" type=\"continuous\"><parent link=\"a\"/><child link=\"b\"/>\
         <dynamics damping=\"0.7\" friction=\"0.2\"/></joint>\
         <joint name=\"k\" type=\"continuous\"><parent link=\"b\"/><child link=\"c\"/></joint></robot>",
        "t.urdf",
    )
    .unwrap();
    let j = &tree.joints[tree.joint("j").unwrap()];
    assert_eq!(
        (j.dynamics.damping, j.dynamics.friction, j.dynamics.armature),
        (0.7, 0.2, 0.0)
    );
    assert_eq!(
        tree.joints[tree.joint("k").unwrap()].dynamics,
        Default::default()
    );
    let tree = screwkit_model::mjcf::load_str(
        r#"<mujoco><default><joint armature="0.1" damping="2"/>
           <default class="light"><joint damping="0.5" frictionloss="0.3"/></default></default>
           <worldbody><body name="a"><joint name="j" type="hinge"/><geom size="0.1"/>
             <body name="b"><joint name="k" class="light" type="hinge"/><geom size="0.1"/></body>
           </body></worldbody></mujoco>"#,
        "t.xml",
        std::path::Path::new("."),
    )
    .unwrap();
    assert_eq!(tree.gravity, None);
    let d = |name: &str| tree.joints[tree.joint(name).unwrap()].dynamics;
    assert_eq!(
        (d("j").armature, d("j").damping, d("j").friction),
        (0.1, 2.0, 0.0)
    );
    assert_eq!(
        (d("k").armature, d("k").damping, d("k").friction),
        (0.1, 0.5, 0.3)
    );
}

/// Issue 44, item 18: mimic chains are followed once per link (each joint's drive was resolved
/// from scratch: 30,000 chained mimics took over 20 s). Joint k follows joint k − 1 with
/// multiplier 1 and offset 1e-4, so joint k turns q + k·1e-4: every drive is checked.
#[test]
fn thirty_thousand_chained_mimics() {
    let n = 30_000;
    let mut t = String::from("<robot name=\"m\"><link name=\"l0\"/>");
    for i in 0..n {
        t.push_str(&format!(
            "<link name=\"l{}\"/><joint name=\"j{i}\" type=\"continuous\"><parent link=\"l{i}\"/><child link=\"l{}\"/><axis xyz=\"0 0 1\"/>{}</joint>",
            i + 1,
            i + 1,
            if i == 0 {
                String::new()
            } else {
                format!("<mimic joint=\"j{}\" multiplier=\"1\" offset=\"1e-4\"/>", i - 1)
            }
        ));
    }
    t.push_str("</robot>");
    let tree = screwkit_model::urdf::load_str(&t, "m.urdf").unwrap();
    let chain = screwkit_model::Chain::from_tree(&tree, None, None).unwrap();
    assert_eq!(chain.variables.len(), 1);
    for (k, j) in chain.joints.iter().enumerate() {
        assert_eq!((j.drive.variable, j.drive.multiplier), (0, 1.0));
        assert!((j.drive.offset - k as f64 * 1e-4).abs() < 1e-9, "{k}");
    }
    let model = screwkit_model::KinematicTree::from_tree(&tree).unwrap();
    assert_eq!(model.variables.len(), 1);
}

/// Review of issue 44: URDF comments never hold "--" (a source named `a---b` made an
/// unreadable file), and a panic inside `collect_reads` leaves no collector behind (a later
/// load would keep its files protected for the life of the process).
#[test]
fn urdf_comments_and_collect_reads_after_a_panic() {
    let text = "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/><joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\"/></joint></robot>";
    for source in ["a---b.urdf", "x--y-", "----"] {
        let tree = urdf::load_str(text, source).unwrap();
        let written = urdf::write(&tree).unwrap();
        assert!(
            urdf::load_str(&written, "back.urdf").is_ok(),
            "{source}: {written}"
        );
    }
    let path = std::env::temp_dir().join(format!("sk-collect-{}.urdf", std::process::id()));
    std::fs::write(&path, text).unwrap();
    let r = std::panic::catch_unwind(|| {
        input::collect_reads(|| {
            let _ = input::read_file(&path);
            panic!("a bug inside a load");
        })
    });
    assert!(r.is_err());
    // Nothing holds the file now, and a new collection holds exactly its own read.
    assert!(input::read_as_input(&path).is_none());
    let (_, held) = input::collect_reads(|| input::read_file(&path).map(|_| ()));
    assert_eq!(held.len(), 1);
    assert!(input::read_as_input(&path).is_some());
    drop(held);
    assert!(input::read_as_input(&path).is_none());
    let _ = std::fs::remove_file(&path);
}
