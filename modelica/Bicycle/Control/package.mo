within Bicycle;
package Control "Rider and autopilot controllers (twins of the Python controllers of cosim)"
  extends Bicycle.Icons.Package;
  annotation(Documentation(info = "<html>
<p>Controllers as blocks with signal connectors in the style of <code>Modelica.Blocks</code>: every
measurement is a <a href=\"modelica://Bicycle.Interfaces.RealInput\">RealInput</a> and every
command a <a href=\"modelica://Bicycle.Interfaces.RealOutput\">RealOutput</a>
(<code>connector RealInput = input Real</code>), declared with its SI quantity and unit, e.g.
<code>RealInput phi(final quantity = \"Angle\", final unit = \"rad\", displayUnit = \"deg\")</code>.
A controller is wired to a bicycle with <code>connect()</code> from the bicycle's outputs to its
inputs and from its outputs to the bicycle's inputs, see
<a href=\"modelica://Bicycle.Examples.WhippleLinearRiderPush\">Examples.WhippleLinearRiderPush</a>.</p>
<p>Each block is exported as an FMU (<code>__Cosim(export = true)</code>) whose inputs and outputs
have the connectors' names: the FMU of <code>PD</code> has the inputs <code>phi</code> and
<code>phi_dot</code> and the output <code>T</code>. Each is the Modelica twin of the Python block of
the same name in <code>cosim.cosimulation.controllers</code> (same parameter, input and output
names and defaults), so a co-simulated system can swap one for the other. The static blocks
(all but <code>PID</code>) pass their inputs through to their outputs without delay.</p>
<p>Sign conventions: a block has none of its own; its signals take those of the bicycle it is
connected to (paper conventions in the second-order models, Meijaard's in the Whipple family),
so the sign of a stabilizing gain depends on the bicycle.</p>
</html>"));
end Control;
