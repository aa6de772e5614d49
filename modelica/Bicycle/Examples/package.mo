within Bicycle;
package Examples "Runnable examples with experiment settings"
  extends Bicycle.Icons.ExamplesPackage;
  annotation(Documentation(info = "<html>
<p>Each example is one model with an <code>experiment</code> annotation. Examples that close a
loop or drive a bicycle compose the bicycle with blocks of
<a href=\"modelica://Bicycle.Control\">Control</a>,
<a href=\"modelica://Bicycle.Rider\">Rider</a> and
<a href=\"modelica://Bicycle.Sources\">Sources</a> through their
<code>RealInput</code>/<code>RealOutput</code> connectors, with <code>connect()</code> only, just as a
co-simulation system file connects the FMUs of the same blocks
(<code>\"bike.phi -&gt; rider.phi\"</code> is <code>connect(bike.phi, rider.phi)</code>).
<code>WhippleLinearRiderPush</code> is <code>cosim/systems/rider-p-control.toml</code> as one model.
Examples without a block bind constant inputs in the bicycle's modifier
(<code>bicycle(T = 0)</code>).</p>
<p>One model closes a loop in continuous time; a co-simulation master holds its inputs over each
communication step. The two agree exactly for sources whose jumps lie on communication points
(Jacobi) and converge at first order in the step for feedback loops
(tests/test_connected_examples.py).</p>
</html>"));
end Examples;
