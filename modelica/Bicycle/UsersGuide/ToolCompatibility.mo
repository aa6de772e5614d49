within Bicycle.UsersGuide;
class ToolCompatibility "Which Modelica tools load the library, and what each checks"
  extends Bicycle.Icons.Information;
  annotation(Documentation(info = "<html>
<p>The library is written to the Modelica Language Specification (MLS 3.6) without the Modelica
Standard Library (its unit types are copied in <code>Bicycle.Units</code>). What was checked, and
with which result:</p>
<table border=\"1\" cellpadding=\"3\">
<tr><th>tool</th><th>check</th><th>result</th></tr>
<tr><td>cosim's compiler (pymoca 0.12 with the project's patches, CasADi 3.7)</td><td>flatten,
index-1 structure, explicit ODE, FMU</td><td>the exported bicycles and examples; the numbers are
checked against the sympy oracle and the published references</td></tr>
<tr><td>rumoca 0.10.2 (<code>rumoca.Session().load</code>)</td><td>parse, flatten with the
one-member flow sets of MLS 9.2, connector balance (MLS 9.3.1), equation count of the flat model
(MLS 4.7)</td><td>every non-partial model of the library compiles balanced, components included
(each compiled as a model of its own)</td></tr>
<tr><td>rumoca 0.10.2 (<code>simulate</code>, relative tolerance 1e-10)</td><td>simulation of
every example over its experiment, and of <code>Whipple</code>, <code>WhippleRider</code> and
<code>WhippleRiderTwist</code> with their inputs bound to zero, started leaning at 5 m/s, over 3
s</td><td>every state and output equals the project's FMU within 5e-9 of max(1, |value|) (the test
requires 1e-6: <code>tests/test_rumoca_simulation.py</code>); rumoca 0.10.2 cannot simulate models
with top-level inputs</td></tr>
<tr><td>OpenModelica, Dymola</td><td>not run (not available here)</td><td>see below</td></tr>
</table>
<h4>What the specification asks that rumoca 0.10.2 does not check</h4>
<ul>
<li><b>Connector balance of typed components.</b> MLS 9.3.1 counts every scalar of a connector;
rumoca counts only components of the built-in types and counts a built-in <code>input Real</code>
as a potential. The library's own test (<code>tests/test_connector_balance.py</code>) counts flow
scalars against scalars that are neither parameter, constant, input, output, stream nor flow for
every connector, for its default size and the next two; every connector is balanced. The causal
variables of the connectors are declared with the <code>Bicycle.Units</code> types.</li>
<li><b>Modifiers of a constraining clause.</b> MLS 7.3.2 applies the modifiers of
<code>constrainedby C(m)</code> to the default and to every replacement; rumoca applies only the
declaration's. The replaceable wheels and hinges of the bicycles repeat them in the declaration,
which every tool applies to the default.</li>
<li><b>Redeclaration of a class with replaceable components.</b> rumoca refuses
<code>redeclare LeanTwistHinge hip</code> as \"not a subtype\" of the constraining class when
<code>LeanTwistHinge</code> has replaceable components; its joints are therefore fixed.</li>
<li><b>Local balance</b> (MLS 4.7): OpenModelica and Dymola check each model's equations against
its unknowns minus the flows and inputs of its connectors; rumoca checks the flat model. Every
component compiles on its own in rumoca, which comes to the same count.</li>
</ul>
<h4>How the library meets the specification</h4>
<ul>
<li>The frame connectors (<code>Mechanics.Interfaces.Frame_a</code>, <code>Frame_b</code>) pass
the kinematics as matching <code>input</code>/<code>output</code> pairs and keep three acausal
pairs (generalized speeds and the joints' speeds, generalized accelerations and forces, gravity and
energy), the fix MLS 9.3.1 prescribes for such frames.</li>
<li>The ground (<code>Mechanics.Ground</code>) is a component; no model reads the flows of its own
top-level connector, so the one-member flow sets of MLS 9.2 add no equation to an assembly.</li>
<li>Joints own their coordinates; an assembly states the number of generalized speeds once.</li>
</ul>
</html>"));
end ToolCompatibility;
