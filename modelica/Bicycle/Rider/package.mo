within Bicycle;
package Rider "Rider models: neuromuscular delay (twins of cosim's Python delay blocks)"
end Rider;
